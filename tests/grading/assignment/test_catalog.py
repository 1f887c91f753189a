"""The assignment's tests (raykit_grading.assignment.catalog): points, stages, callees, the graded
draws."""

from __future__ import annotations

import json

import numpy as np
import pytest

from raykit_grading.assignment.catalog import HIDDEN, TESTS, VISIBLE


def test_every_visible_array_test_with_a_callee_names_it():
    for test in TESTS:
        if test.task in ("rays_through", "line_rays"):
            assert test.callees, test.name
    assert any(t.visibility == VISIBLE and t.callees for t in TESTS)


@pytest.mark.slow
def test_catalog_has_points_visibility_and_every_stage():
    assert {t.visibility for t in TESTS} == {VISIBLE, HIDDEN}
    assert {t.stage.split()[0] for t in TESTS} == {"1", "2", "3", "4", "5"}
    assert len({t.name.split()[0] for t in TESTS}) == len(TESTS)
    assert all(t.points > 0 for t in TESTS)


@pytest.mark.slow
def test_graded_draws_differ_from_the_public_ones_and_repeat_under_their_seed():
    for test in TESTS:
        public, graded = test.public_inputs(), test.graded_inputs(7)
        again = test.graded_inputs(7)
        assert json.dumps(graded[0]) == json.dumps(again[0]), test.name
        assert all(np.array_equal(graded[1][k], again[1][k]) for k in graded[1]), test.name
        differs = json.dumps(public[0], default=str) != json.dumps(graded[0], default=str) or any(
            not np.array_equal(public[1][k], graded[1][k]) for k in public[1]
        )
        assert differs, test.name
        if test.kind == "image":  # a shipped reference picture cannot even have the shape
            camera = graded[0]["scene"]["camera"]
            shipped = public[0]["scene"]["camera"]
            size = ("width", "height") if "eye" in camera else ("pixels",)
            assert [camera[k] for k in size] != [shipped[k] for k in size], test.name

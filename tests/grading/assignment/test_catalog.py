"""The assignment's tests (raykit_grading.assignment.catalog): points, stages, callees, the graded
draws."""

from __future__ import annotations

from raykit_grading.assignment.catalog import TESTS, VISIBLE


def test_every_visible_array_test_with_a_callee_names_it():
    for test in TESTS:
        if test.task in ("rays_through", "line_rays"):
            assert test.callees, test.name
    assert any(t.visibility == VISIBLE and t.callees for t in TESTS)

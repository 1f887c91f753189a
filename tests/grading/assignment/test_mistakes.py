"""The classic mistakes (raykit_grading.assignment.mistakes): each blamed on a function the student
writes, each applied where the renderer reads it."""

from __future__ import annotations

import re

import numpy as np
import pytest

from conftest import REPO
from raykit_grading.assignment.mistakes import MISTAKES


def test_every_mistake_is_blamed_on_a_function_the_student_writes():
    """``where`` names the functions the release leaves to write (its stubs), never given code
    a student function calls (such as Camera.plane_size, read by _in_plane)."""
    from raykit_grading.assignment.catalog import REPO
    from raykit_grading.assignment.markers import strip_solutions

    stubs = set()
    for source in (REPO / "raykit").rglob("*.py"):
        names = strip_solutions(source.read_text(), str(source))[1]
        stubs |= {f"{source.relative_to(REPO)}: {name}" for name in names}
    for mistake in MISTAKES:
        named = re.findall(r"(raykit/[\w/]+\.py: [\w.]+)", mistake.where)
        assert named and set(named) <= stubs, (mistake.key, named)


@pytest.mark.slow
def test_mistakes_apply_to_a_camera_that_has_already_computed_its_frame():
    from dataclasses import replace

    from raykit.io.scene_json import load_scene
    from raykit.render import render

    scene = load_scene(REPO / "scenes/classic.json")
    scene = replace(scene, camera=replace(scene.camera, width=80, height=60))
    right = render(scene).rgb  # the camera caches its u, v, w here
    for key in ("u_v_swapped", "u_negated"):
        with next(m for m in MISTAKES if m.key == key).active():
            assert not np.array_equal(render(scene).rgb, right), key

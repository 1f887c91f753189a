"""The classic mistakes (raykit_grading.assignment.mistakes): each blamed on a function the student
writes, each applied where the renderer reads it."""

from __future__ import annotations

import re

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

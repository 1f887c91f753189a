"""The solution markers (raykit_grading.assignment.markers): each marked function becomes a stub
that raises with its hint."""

from __future__ import annotations

import pytest

from conftest import REPO
from raykit_grading.assignment.markers import MarkerError, strip_solutions


def test_markers_become_stubs_with_the_hint_and_must_balance():
    source = (
        'def f(x):\n    """Doc."""\n    # BEGIN SOLUTION\n    # hint: add one\n'
        "    #       to x\n    return x + 1\n    # END SOLUTION\n"
    )
    stripped, names = strip_solutions(source)
    assert names == ["f"]
    assert stripped == (
        'def f(x):\n    """Doc."""\n    raise NotImplementedError('
        "'f: write this function. Hint: add one to x')\n"
    )
    with pytest.raises(MarkerError):
        strip_solutions("def f():\n    # BEGIN SOLUTION\n    pass\n")
    with pytest.raises(MarkerError):
        strip_solutions("def f():\n    pass\n    # END SOLUTION\n")


def test_every_marked_function_in_raykit_has_a_hint():
    for path in (REPO / "raykit").rglob("*.py"):
        stripped, _ = strip_solutions(path.read_text(), str(path))
        assert "Hint: see the lecture slides" not in stripped, path

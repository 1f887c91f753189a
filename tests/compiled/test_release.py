"""The grader and the starter kit with numba installed: the compiled engine never stands in for a
student's functions, and is never shipped."""

from __future__ import annotations


def test_a_wrong_submission_still_renders_wrong_with_numba_installed(tmp_path, child_python):
    """The grader runs the student's own numpy functions: the compiled engine never stands in."""
    from mistaken_submissions import make_submission
    from raykit_grading.grading.grade import Options, grade

    submission = make_submission(tmp_path, "rows_flipped")
    assert (submission / "raykit/engine/compiled/spheres.py").exists()  # even with it there
    results = grade(submission, options=Options(child_python), names=["3.6"])
    (test,) = results["tests"]
    assert test["score"] == 0, test


def test_the_starter_kit_ships_no_compiled_engine(tmp_path):
    from raykit_grading.assignment.release import build_release

    build_release(tmp_path / "kit")
    assert not (tmp_path / "kit/raykit/engine/compiled").exists()
    assert (tmp_path / "kit/raykit/engine/choice.py").exists()

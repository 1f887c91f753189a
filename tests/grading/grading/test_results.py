"""The results file's entries and the summary shown at once (raykit_grading.grading.results)."""

from __future__ import annotations

from raykit_grading.assignment.catalog import VISIBLE, by_name


def test_the_summary_shown_at_once_sums_the_visible_tests_and_tells_no_hidden_outcome():
    """Two results that differ only in how the hidden tests went (all passed, all failed)
    give the same summary: the visible tests' sums, then the hidden tests' count and points."""
    from raykit_grading.grading.results import stage_lines, test_entry

    tests = by_name(["2.1", "2.3", "2.4", "2.5", "3.6", "3.8"])
    passed = [test_entry(t, t.points, "") for t in tests]
    failed = [e if t.visibility == VISIBLE else test_entry(t, 0.0, "") for t, e in
              zip(tests, passed, strict=True)]  # fmt: skip
    assert (
        stage_lines(tests, passed)
        == stage_lines(tests, failed)
        == [
            "Stage 2 rays, planes and spheres: 4 of 4 points, 2 of 2 visible tests pass",
            "Stage 3 renderer: 4 of 4 points, 1 of 1 visible tests pass",
            "Hidden tests: 3, 5 points (how they went is not shown here)",
        ]
    )

"""Right submissions keep their score as deployed, whatever else they do that is harmless."""

from __future__ import annotations

import pytest

from hostile.deployed import (
    POINTS,
    grade_as_deployed,
    scores,
    submission_wrapping,
)
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS

pytestmark = pytest.mark.slow


def test_a_right_submission_that_writes_to_devnull_keeps_its_score(autograder, tmp_path):
    """Quieting output into os.devnull works in every sandbox: the chroot tree's /dev/null is
    mode 666 (mknod took the umask) and Landlock lets the child write it, so Gradescope's
    sandbox scores this as bubblewrap does."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os\n"
        "    with open(os.devnull, 'w') as quiet:\n        quiet.write('progress')\n"
        "    return _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results


def test_a_correct_submission_scores_full_marks_as_deployed(autograder, tmp_path):
    results, run = grade_as_deployed(
        autograder,
        make_submission(tmp_path / "submission"),
        [t.key for t in TESTS],
        tmp_path,
        wall=None,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    failed = [(t["number"], t["output"][:300]) for t in results["tests"] if t["status"] != "passed"]
    assert failed == []
    assert results["score"] == pytest.approx(sum(POINTS.values()))

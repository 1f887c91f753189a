"""Links and special files in the submission, and zip tricks, are never followed (2)."""

from __future__ import annotations

import os
import zipfile

import pytest

from conftest import REPO
from hostile.deployed import (
    grade_as_deployed,
    scores,
    way,
)
from mistaken_submissions import make_submission

pytestmark = pytest.mark.slow


# ---- 2: links and special files in the submission are never followed ------------------------


def test_2_a_raykit_that_is_a_link_to_the_reference_scores_zero(autograder, tmp_path):
    submission = tmp_path / "submission"
    submission.mkdir()
    (submission / "raykit").symlink_to(REPO / "raykit")
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert scores(results) == {"2.1": 0, "3.6": 0}
    assert "raykit is a symbolic link: not followed" in results["output"]
    assert "no raykit package" in results["tests"][0]["output"]
    if way(autograder) == "prairielearn":  # the wrong shape: not gradable, not a zero
        assert results["prairielearn"]["gradable"] is False
    assert run.returncode == 0  # graded (a zero, with the reason): exit 0, whatever the score


def test_2_linked_modules_fifos_and_zip_tricks_are_left_out(release, autograder, tmp_path):
    """planes.py a link to the reference's, a FIFO beside it: planes.py is missing, so every
    test that needs it fails; the FIFO is never opened (no hang)."""
    submission = make_submission(tmp_path / "submission")
    (submission / "raykit/planes.py").unlink()
    (submission / "raykit/planes.py").symlink_to(REPO / "raykit/planes.py")
    os.mkfifo(submission / "raykit/pipe.py")
    results, run = grade_as_deployed(autograder, submission, ["2.1", "2.3"], tmp_path)
    assert scores(results) == {"2.1": 0, "2.3": 2}, results
    assert "raykit/planes.py is a symbolic link: left out" in results["output"]
    assert "raykit/pipe.py is a named pipe (FIFO): left out" in results["output"]


def test_2_a_zipped_submission_is_unpacked_without_links_or_escapes(autograder, tmp_path):
    solution = make_submission(tmp_path / "solution")
    submission = tmp_path / "submission"
    submission.mkdir()
    with zipfile.ZipFile(submission / "work.zip", "w") as archive:
        for path in sorted((solution / "raykit").rglob("*.py")):
            archive.write(path, f"mine/{path.relative_to(solution)}")
        link = zipfile.ZipInfo("mine/raykit/evil.py")
        link.external_attr = 0o120777 << 16  # a symbolic link to the grader
        archive.writestr(link, "/autograder/source/raykit/planes.py")
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "evil.py is a link: left out" in results["output"]

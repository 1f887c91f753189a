"""The grader's own: forged results and a killed parent change nothing (7); a grader that
cannot grade says so, before grading anyone (8)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import pytest

from hostile.deployed import (
    grade_as_deployed,
    scores,
)
from mistaken_submissions import make_submission

pytestmark = pytest.mark.slow


# ---- 7: the results are the grader's; killing it loses nothing ----------------------------


def test_7_forged_results_and_a_killed_parent_change_nothing(release, autograder, tmp_path):
    targets = [
        str(autograder / "results/results.json"),
        str(tmp_path / "results/results.json"),
        "/autograder/results/results.json",  # where the container way's grader writes it
    ]
    code = (
        "import json, os, signal\n"
        f"for path in {targets!r}:\n"
        "    try:\n"
        "        open(path, 'w').write(json.dumps({{'score': 1000, 'tests': []}}))\n"
        "    except OSError:\n        pass\n"
        "for pid in (os.getppid(), 1, -1):\n"
        "    try:\n        os.kill(pid, signal.SIGKILL)\n"
        "    except OSError:\n        pass\n"
    )
    submission = tmp_path / "submission"
    shutil.copytree(release / "raykit", submission / "raykit")
    with open(submission / "raykit/__init__.py", "a") as module:
        module.write("\n" + code.replace("{{", "{").replace("}}", "}"))
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": 0, "3.6": 0}
    assert results["score"] == 0 and len(results["tests"]) == 2


# ---- 8: a grader that cannot grade says so, before grading anyone --------------------------


def test_8_no_usable_child_python_is_one_line_and_a_non_zero_exit(tmp_path):
    submission = make_submission(tmp_path / "submission")
    out = tmp_path / "r.json"
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o", str(out),
         "--only", "2.1", "--child-python", "/nonexistent/python3"],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert run.returncode == 3
    assert "Traceback" not in run.stderr
    assert run.stderr.startswith("raykit_grading: error: cannot grade: cannot run the child")
    results = json.loads(out.read_text())
    assert results["tests"][0]["output"].startswith("NOT GRADED")
    batch = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "batch", str(tmp_path), "-o",
         str(tmp_path / "out"), "--child-python", "/nonexistent/python3"],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert batch.returncode == 3 and "Traceback" not in batch.stderr
    assert not (tmp_path / "out/scores.csv").exists()

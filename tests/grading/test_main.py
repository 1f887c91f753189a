"""The grader's command line (raykit_grading.__main__): grade, batch and tests, and bad input
refused in one line."""

from __future__ import annotations

import subprocess
import sys
import zipfile

import pytest

from conftest import REPO
from raykit_grading.assignment.catalog import TESTS


@pytest.mark.parametrize("as_zip", [False, True], ids=["folder", "zip"])
def test_grading_command_line_writes_results(tmp_path, child_python, solution, as_zip):
    """``grade`` takes the student's folder, or their zip as the student README makes it."""
    submission = solution
    if as_zip:
        submission = tmp_path / "ada.zip"
        with zipfile.ZipFile(submission, "w") as archive:
            for path in sorted((solution / "raykit").rglob("*.py")):
                archive.write(path, path.relative_to(solution).as_posix())
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(submission),
         "-o", str(tmp_path / "r.json"), "--child-python", child_python, "--only", "1.1", "2.1"],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == f"wrote {tmp_path / 'r.json'}: 3 of 3 points"


@pytest.mark.parametrize(
    "arguments, status, says",
    [
        (["batch", "no/such/folder", "-o", "out"], 2, "no/such/folder: no such folder"),
        (["grade", "no/such/folder", "-o", "r.json"], 2, "no/such/folder: no such folder or zip"),
        (["grade", "no/such.zip", "-o", "r.json"], 2, "no/such.zip: no such zip"),
        (["grade", ".", "-o", "r.json", "--only", "9.9"], 2, "--only 9.9: no test has that"),
        (["grade", ".", "-o", "r.json", "--wall", "3"], 2, "unrecognized arguments: --wall"),
    ],
)
def test_grading_command_line_refuses_bad_input_in_one_line(tmp_path, arguments, status, says):
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", *arguments],
        capture_output=True,
        text=True,
        cwd=tmp_path,
    )
    assert run.returncode == status
    assert says in run.stderr and "Traceback" not in run.stderr
    assert not (tmp_path / "out").exists() and not (tmp_path / "r.json").exists()


def test_the_tests_command_lists_each_stage_with_its_totals():
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "tests"], capture_output=True, text=True,
        cwd=REPO, check=True,
    )  # fmt: skip
    lines = run.stdout.splitlines()
    headings = [line for line in lines if line.startswith("Stage ")]
    assert [h.split(":")[0] for h in headings] == [
        "Stage 1 line-scan camera", "Stage 2 rays, planes and spheres", "Stage 3 renderer",
        "Stage 4 shading, shadows and mirrors", "Stage 5 distributed ray tracing",
    ]  # fmt: skip
    total = sum(t.points for t in TESTS)
    assert lines[-1].startswith(f"Total: {len(TESTS)} tests, {total:g} points")
    assert sum(line.startswith("  ") for line in lines) == len(TESTS)

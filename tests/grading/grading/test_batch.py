"""A class graded by ``batch`` (raykit_grading.grading.batch), end to end by the documented
command (tests/conftest.py's ``graded_class``): every entry's status and score or why not, a
submission or a module that does not import, each stage summed up, a run again grading no one;
the hidden tests' pictures kept out of what a student may be handed; one student at a time in
a container's memory. The class report and the students' pages it writes are test_report.py's."""

from __future__ import annotations

import csv
import html
import json
import os
import re
import subprocess
import sys
from urllib.parse import unquote

import pytest

from conftest import CLASS_TESTS, REPO
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS, VISIBLE
from raykit_grading.grading.batch import JOBS, jobs_within
from raykit_grading.grading.grade import Options
from raykit_grading.grading.results import NOT_IMPORTED
from raykit_grading.sandbox.confine import ContainerLimits


def test_batch_grades_every_entry_of_a_mixed_class_or_says_why_not(graded_class):
    out, run = graded_class
    assert run.returncode == 0, run.stderr[-3000:]  # every submission graded: notes.txt is none
    rows = {row["student"]: row for row in csv.DictReader((out / "scores.csv").open())}
    assert {name: (row["status"], row["score"]) for name, row in rows.items()} == {
        "ada": ("graded", "7.0"),
        "erin": ("graded", "7.0"),
        "Grace Hopper": ("graded", "7.0"),
        "hal": ("graded", "1.0"),  # only the camera frame: no sphere is hit
        "mo": ("graded", "2.0"),  # the frame and the render show u and v swapped
        "Alan Turing & Kathleen O'Brien": ("graded", "2.0"),
        "flo": ("graded", "3.0"),  # the render is upside down
        "bo": ("does not import", "0.0"),
        "cy": ("graded", "3.0"),  # what needs mirrors.py (the render) fails, the rest passes
        "notes.txt": ("not a submission: not a folder or a zip", ""),
    }
    said = "9 submissions: 8 graded, 1 whose raykit does not import (0 points); 1 entry is not a"
    assert f"{said} submission\n" in run.stdout  # in the class report's words
    assert "left out, not submissions:\n  notes.txt: not a submission: not a folder" in run.stderr
    assert "not graded:" not in run.stderr


def test_the_batch_run_again_grades_no_one_and_exits_0_as_every_submission_is_graded(graded_class):
    out, first = graded_class
    graded = {p: p.stat().st_mtime_ns for p in out.glob("feedback/*/results.json")}
    again = subprocess.run(first.args, capture_output=True, text=True, cwd=out.parent, timeout=600)
    assert again.returncode == 0, again.stderr[-3000:]
    assert {p: p.stat().st_mtime_ns for p in graded} == graded  # no one graded again
    assert "9 submissions: 8 graded, 1 whose raykit does not import" in again.stdout


def test_a_submission_that_does_not_import_says_its_error_once_and_runs_no_test(graded_class):
    out, _ = graded_class
    results = json.loads((out / "feedback/bo/results.json").read_text())
    assert [t["output"] for t in results["tests"]] == [NOT_IMPORTED] * len(CLASS_TESTS)
    assert results["score"] == 0
    assert "raykit does not import" in results["output"]
    assert "SyntaxError" in results["extra_data"]["does_not_import"]
    assert 'raykit/__init__.py", line' in results["output"]  # where, from the student's file
    assert "/work/child.py" not in results["output"]  # not the grader's frames


def test_a_module_that_does_not_import_is_noted_once_and_fails_only_its_tests(graded_class):
    out, _ = graded_class
    results = json.loads((out / "feedback/cy/results.json").read_text())
    noted = (  # and those importing it, with why: the error, its file and line
        "Note: raykit.mirrors, raykit.render, raykit.shading: do not import (SyntaxError: "
        "invalid syntax (in raykit/mirrors.py, line "
    )
    line = next(li for li in results["output"].splitlines() if li.startswith(noted))
    assert line.endswith(")); the tests that use them fail"), line
    assert {t["number"]: t["score"] for t in results["tests"]} == {"2.3": 2, "3.1": 1, "3.6": 0}
    assert "SyntaxError" in results["tests"][2]["output"]


def test_results_sum_up_each_stage_and_carry_the_diagnosed_mistake(graded_class):
    out, _ = graded_class
    mo = json.loads((out / "feedback/mo/results.json").read_text())
    assert mo["output"].splitlines()[1:] == [
        "Stage 2 rays, planes and spheres: 2 of 2 points, 1 of 1 visible tests pass",
        "Stage 3 renderer: 0 of 5 points, 0 of 2 visible tests pass",
    ]
    render = next(t for t in mo["tests"] if t["number"] == "3.6")
    assert render["extra_data"] == {
        "mistake": "u_v_swapped",
        "says": "u and v are swapped",
        "where": render["extra_data"]["where"],  # which function: another change's to make
    }


def test_a_students_feedback_folder_holds_nothing_of_the_hidden_tests(tmp_path):
    """feedback/<student>/ may be handed to the student: the hidden tests' pictures are in
    hidden/<student>/, and the class report takes its example from there if it must."""
    make_submission(tmp_path / "class/mo", "u_v_swapped")
    hidden = "3.8"  # render scenes/orthographic.json
    assert next(t for t in TESTS if t.key == hidden).visibility != VISIBLE
    out = tmp_path / "graded"
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "batch", str(tmp_path / "class"), "-o", str(out),
         "--only", "3.6", hidden],
        capture_output=True, text=True, cwd=tmp_path, timeout=900,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr[-2000:]
    assert sorted(p.name for p in (out / "feedback/mo").iterdir()) == [
        "3.6.png", "index.html", "results.json"
    ]  # fmt: skip
    assert (out / f"hidden/mo/{hidden}.png").is_file()
    said = {t["number"]: t["output"] for t in json.loads((out / "feedback/mo/results.json")
                                                          .read_text())["tests"]}  # fmt: skip
    assert "3.6.png" in said["3.6"]  # the picture it gets is named, the hidden one's is not
    assert "feedback picture" not in said[hidden] and ".png" not in said[hidden], said[hidden]
    page = html.unescape((out / "report.html").read_text())
    examples = re.findall(r"<img class='example' src='([^']+)'", page)
    assert examples and all((out / unquote(src)).is_file() for src in examples)


def test_batch_grades_one_student_at_a_time_in_a_container_with_a_memory_limit():
    no_limit, limit = ContainerLimits(None, None), ContainerLimits(768 << 20, 0.5)
    assert jobs_within(None, no_limit) == (JOBS, None)
    assert jobs_within(4, no_limit) == (4, None)
    assert jobs_within(1, limit) == (1, None)
    jobs, why = jobs_within(4, limit)
    assert jobs == 1 and "not 4" in why and "768 MB" in why


def test_batch_in_docker_s_confinement_says_it_grades_one_student_at_a_time(tmp_path):
    """Asked for 4 at once in a container of 768 MB (Docker's confinement emulated), batch
    grades the two students one after the other, says so, and grades both in full."""
    if os.geteuid() != 0:
        pytest.skip("emulating Docker's confinement needs root")
    students = tmp_path / "submissions"
    make_submission(students / "ada")
    make_submission(students / "zoe")
    out = tmp_path / "graded"
    run = subprocess.run(
        [sys.executable, str(REPO / "tests" / "support" / "docker_confinement.py"),
         "--memory-mb", "768", "--", sys.executable, "-m", "raykit_grading", "batch",
         str(students), "-o", str(out), "--only", "2.3", "--jobs", "4", "--seed", "7"],
        capture_output=True, text=True, cwd=REPO, timeout=600,
    )  # fmt: skip
    if run.returncode == 77:
        pytest.skip(run.stderr.strip())
    assert run.returncode == 0, run.stderr[-3000:]
    assert "one student at a time, not 4: this container's 768 MB" in run.stderr
    rows = {row["student"]: row for row in csv.DictReader((out / "scores.csv").open())}
    assert {k: (r["status"], r["score"] == r["max_score"]) for k, r in rows.items()} == {
        "ada": ("graded", True),
        "zoe": ("graded", True),
    }


def test_batch_grades_a_folder_into_a_csv_and_a_feedback_folder_each(
    tmp_path, child_python, release
):
    import csv
    import shutil

    from raykit_grading.grading.batch import grade_folder

    students = tmp_path / "submissions"
    make_submission(students / "ada")
    make_submission(students / "bob", "u_v_swapped")
    shutil.copytree(release / "raykit", students / "cy" / "raykit")
    status = grade_folder(
        students,
        tmp_path / "out",
        jobs=2,
        options=Options(child_python),
        names=["2.1", "3.6"],
        assignment=tmp_path,
    )
    assert status == 0
    rows = {row["student"]: row for row in csv.DictReader((tmp_path / "out/scores.csv").open())}
    assert set(rows) == {"ada", "bob", "cy"}
    assert float(rows["ada"]["score"]) == float(rows["ada"]["max_score"]) == 6
    assert float(rows["bob"]["score"]) == 2 and float(rows["cy"]["score"]) == 0
    assert rows["bob"]["3.6"] == "0.0" and rows["bob"]["2.1"] == "2"
    bob = json.loads((tmp_path / "out/feedback/bob/results.json").read_text())
    assert "u and v are swapped" in bob["tests"][1]["output"]
    assert (tmp_path / "out/feedback/bob/3.6.png").is_file()

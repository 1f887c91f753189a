"""The autograder: the solution scores full marks, the student release 0, each classic mistake
is named, and results.json follows Gradescope's specification."""

import html
import json
import subprocess
import sys
import zipfile

import jsonschema
import pytest
import tomllib

from conftest import REPO
from mistaken_submissions import EDITS, make_rewritten, make_submission
from raykit_grading.assignment.catalog import TESTS, VISIBLE
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.grading.grade import Options, grade, grade_to_file

# Gradescope's results.json, as its autograder specification documents it
RESULTS_SCHEMA = {
    "type": "object",
    "required": ["tests"],
    "properties": {
        "score": {"type": "number"},
        "execution_time": {"type": "number"},
        "output": {"type": "string"},
        "visibility": {"enum": ["hidden", "after_due_date", "after_published", "visible"]},
        "stdout_visibility": {"enum": ["hidden", "after_due_date", "after_published", "visible"]},
        "extra_data": {"type": "object"},
        "tests": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["score", "max_score", "name", "output", "visibility"],
                "properties": {
                    "score": {"type": "number"},
                    "max_score": {"type": "number"},
                    "status": {"enum": ["passed", "failed"]},
                    "name": {"type": "string"},
                    "number": {"type": "string"},
                    "output": {"type": "string"},
                    "tags": {"type": "array", "items": {"type": "string"}},
                    "visibility": {
                        "enum": ["hidden", "after_due_date", "after_published", "visible"]
                    },
                },
            },
        },
    },
}
TOTAL = sum(t.points for t in TESTS)


@pytest.fixture(scope="session")
def solution(tmp_path_factory):
    return make_submission(tmp_path_factory.mktemp("solution"))


def test_solution_scores_full_marks_in_a_valid_results_file(solution, child_python, tmp_path):
    status = grade_to_file(
        solution,
        tmp_path / "results.json",
        options=Options(child_python),
        feedback=tmp_path / "feedback",
    )
    assert status == 0
    written = results = json.loads((tmp_path / "results.json").read_text())
    jsonschema.validate(written, RESULTS_SCHEMA)
    failed = [(t["name"], t["output"]) for t in written["tests"] if t["score"] < t["max_score"]]
    assert failed == []
    assert results["score"] == pytest.approx(TOTAL)
    assert {t["visibility"] for t in written["tests"]} == {"visible", "after_due_date"}
    assert len(list((tmp_path / "feedback").glob("*.png"))) == sum(t.kind == "image" for t in TESTS)


def test_execution_time_ends_at_the_last_visible_test(tmp_path, monkeypatch):
    """execution_time is shown at once: it stops where the hidden tests start, so how long they
    ran (a hidden input that makes the code loop) never shows before the due date. The grader's
    clock here is one that each test advances, 1 s a visible test, 100 s a hidden one."""
    import types

    from raykit_grading.grading import grade as grading
    from raykit_grading.grading.results import test_entry

    now = [0.0]

    class Sandbox:  # what grade asks of one, running nothing
        description = "none: a test's stand-in"

        def oom_count(self) -> None:
            return None

    def graded(sandbox, test, *args):
        now[0] += 1.0 if test.visibility == VISIBLE else 100.0
        return test_entry(test, test.points, "")

    monkeypatch.setattr(grading, "choose_sandbox", lambda *args: Sandbox())
    monkeypatch.setattr(grading, "_import_error", lambda *args: ("", []))
    monkeypatch.setattr(grading, "_grade_one", graded)
    clock = types.SimpleNamespace(perf_counter=lambda: now[0], monotonic=lambda: now[0])
    monkeypatch.setattr(grading, "time", clock)
    (tmp_path / "raykit").mkdir()
    (tmp_path / "raykit" / "__init__.py").write_text("")
    results = grade(tmp_path, names=["2.4", "2.3", "2.5", "2.6"])  # 2.4, 2.5 hidden
    assert [t["number"] for t in results["tests"]] == ["2.3", "2.4", "2.5", "2.6"]
    assert now[0] == 202.0 and results["execution_time"] == 2.0


def test_grader_scores_the_bare_release_zero_and_says_what_to_write(release, child_python):
    results = grade(release, options=Options(child_python))
    assert results["score"] == 0
    assert all(t["output"].startswith("not written yet") for t in results["tests"])
    visible = [t["output"] for t in results["tests"] if t["visibility"] == "visible"]
    assert any("/submission/raykit/" in output for output in visible)  # where it stopped
    assert not any("child.py" in output or "tasks.py" in output for output in visible)


def test_submission_without_a_package_scores_zero(tmp_path, child_python):
    (tmp_path / "notes.txt").write_text("oops")
    results = grade(tmp_path, options=Options(child_python))
    assert results["score"] == 0 and "no raykit package" in results["tests"][0]["output"]


@pytest.mark.parametrize(
    "key", sorted(k for k in EDITS if next(m for m in MISTAKES if m.key == k).in_renders)
)
def test_each_classic_mistake_is_named_in_the_feedback(key, tmp_path, child_python):
    submission = make_submission(tmp_path, key)
    mistake = next(m for m in MISTAKES if m.key == key)
    says = mistake.says
    names = {
        "1": ["1.6", "1.7"],  # a scan and a sweep of the line-scan camera
        "3": ["3.6", "3.8", "3.9", "3.11"],  # classic, parallel rays, inside a ring, overlaps
        "4": ["4.8", "4.10", "4.11"],  # lit classic, mirrors, at 1e6 with a touching ball
        "5": ["5.16", "5.17", "5.18", "5.19", "5.20"],  # light, lens, glossy, blur, hidden
    }[mistake.stage]
    results = grade(submission, options=Options(child_python), names=names)
    outputs = [html.unescape(t["output"]) for t in results["tests"]]
    assert any(f"when {says}" in out for out in outputs), outputs
    for out in outputs:  # no other mistake is named instead
        assert all(f"when {m.says}" not in out for m in MISTAKES if m.key != key)


STAGE5 = [t.key for t in TESTS if t.stage.startswith("5")]


def test_stage5_written_right_another_way_scores_in_full(tmp_path, child_python):
    # the renders' noise reaches pixels through the student's own jittered_point, point_in_pixel,
    # point_on_lens and sampled: rounded otherwise, the same picture within the comparison's
    # tolerance, under any seed
    submission = make_rewritten(tmp_path / "rewritten")
    for seed in (5, 2026):
        results = grade(submission, options=Options(child_python), names=STAGE5, seed=seed)
        failed = [(t["number"], t["output"]) for t in results["tests"]
                  if t["score"] < t["max_score"]]  # fmt: skip
        assert failed == []
        assert results["score"] == pytest.approx(sum(t.points for t in TESTS if t.key in STAGE5))


def test_no_mistake_is_named_for_the_solution(solution, child_python):
    names = ["3.6", "3.9", "3.11", "4.8", "4.10", "4.11", "5.16", "5.18", "5.19", "5.20"]
    results = grade(solution, options=Options(child_python), names=names)
    assert not any("Diagnosis:" in t["output"] for t in results["tests"])


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


def test_the_wheel_holds_raykit_and_its_grader_but_no_hidden_scenes():
    from setuptools import find_packages

    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages = find_packages(str(REPO), include=config["packages"]["find"]["include"])
    assert "grading" not in packages and "raykit_grading" in packages
    assert {p.split(".")[0] for p in packages} == {"raykit", "raykit_grading"}
    data = config.get("package-data", {})
    assert all("scenes" not in pattern for patterns in data.values() for pattern in patterns)
    assert not list((REPO / "raykit_grading").rglob("*.json"))


def test_the_grader_says_plainly_when_it_has_no_clone_to_read_scenes_from(monkeypatch, tmp_path):
    import raykit_grading.grading.grade as grade

    monkeypatch.setattr(grade, "HIDDEN_SCENES", tmp_path / "nowhere")
    with pytest.raises(grade.GradingImpossible, match="needs a clone of the course repository"):
        grade.check_clone()

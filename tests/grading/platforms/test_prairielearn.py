"""PrairieLearn (:mod:`raykit_grading.platforms.prairielearn`): the folder ``prairielearn -o``
writes, PrairieLearn's results.json, and the image run as PrairieLearn's grader host runs it.

The hostile suite's ``prairielearn`` way (tests/grading/hostile/) grades every
attack through the same image; here: no secret in the image, the question's files, the
conversion of results (hidden tests as one line, pictures within 1 MB), a wrong-shaped
submission not gradable, and exact scores in the container for an honest, a mistaken and a
wrong-shaped submission.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import REPO
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS, VISIBLE
from raykit_grading.assignment.seeds import HEADER, fingerprint, read_seed_file
from raykit_grading.platforms import containers, prairielearn

SEED = 20261123


def _seed_file(folder: Path) -> Path:
    path = folder / "grading-seed"
    path.write_text(f"{HEADER}{SEED}\n")
    path.chmod(0o600)
    return path


def _written(tmp_path: Path, *options: str) -> Path:
    tmp_path.mkdir(parents=True, exist_ok=True)
    out = tmp_path / "pl"
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "prairielearn", "-o", str(out), "--image",
         "course/raykit-grader:1", "--seed-file", str(_seed_file(tmp_path)), *options],
        capture_output=True, text=True, cwd=REPO,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    return out


def test_the_image_holds_no_secret_and_the_question_holds_the_seed_and_hidden_scenes(tmp_path):
    out = _written(tmp_path)
    image_files = {p.relative_to(out / "grader-image").as_posix()
                   for p in (out / "grader-image").rglob("*") if p.is_file()}  # fmt: skip
    assert {"Dockerfile", "source/setup.sh", "source/run_prairielearn",
            "source/grader-requirements.txt", "source/raykit_grading/platforms/prairielearn.py",
            "source/raykit/render.py", "source/scenes/classic.json"} <= image_files  # fmt: skip
    assert not any("hidden" in name or "grading-seed" in name for name in image_files)
    for path in (out / "grader-image").rglob("*"):
        if path.is_file():
            assert str(SEED).encode() not in path.read_bytes(), path
    tests = out / "questions/raykit/tests"
    assert (tests / "grading-seed").read_text().strip().endswith(str(SEED))
    hidden = sorted(p.name for p in (tests / "hidden-scenes").iterdir())
    assert hidden == sorted(p.name for p in (REPO / "grading/hidden-scenes").iterdir())
    info = json.loads((out / "questions/raykit/info.json").read_text())
    assert info["gradingMethod"] == "External"
    assert info["externalGradingOptions"] == {
        "enabled": True, "image": "course/raykit-grader:1",
        "entrypoint": "/grader/run_prairielearn", "timeout": 600, "enableNetworking": False,
    }  # fmt: skip
    html = (out / "questions/raykit/question.html").read_text()
    assert '<pl-file-upload file-names="raykit.zip">' in html
    assert "<pl-external-grader-results>" in html
    readme = (out / "README.md").read_text()
    assert f"docker build -t course/raykit-grader:1 {out}/grader-image" in readme


def test_where_no_registry_answers_the_guide_and_the_folder_name_a_local_base(tmp_path):
    """The Dockerfile's FROM pulls ubuntu:22.04 from Docker Hub; the README says how to build
    on the Debian base try-zip uses, and --base-image makes that base the Dockerfile's own
    (the image built on it in the hostile suite's prairielearn way)."""
    readme = (_written(tmp_path / "hub") / "README.md").read_text()
    assert "python -m raykit_grading.platforms.containers base-image" in readme
    local = containers.DEBIAN_BASE
    assert f"docker build --build-arg BASE_IMAGE={local} -t course/raykit-grader:1" in readme
    out = _written(tmp_path / "local", "--base-image", local)
    assert (
        f"ARG BASE_IMAGE={local}\nFROM ${{BASE_IMAGE}}\n"
        in (out / "grader-image/Dockerfile").read_text()
    )


def test_writing_again_keeps_the_question_uuid_and_the_seed(tmp_path):
    out = _written(tmp_path)
    first = json.loads((out / "questions/raykit/info.json").read_text())["uuid"]
    again = subprocess.run(  # in the assignment folder, which holds the seed _written gave
        [sys.executable, "-m", "raykit_grading", "prairielearn", "-o", str(out)],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert again.returncode == 0 and "your Docker Hub name" in again.stderr
    assert f"assignment seed {fingerprint(SEED)} (./grading-seed)" in again.stderr
    assert json.loads((out / "questions/raykit/info.json").read_text())["uuid"] == first
    assert read_seed_file(out / "questions/raykit/tests/grading-seed") == SEED


def _graded(entries: list[tuple[str, float, str]]) -> dict:
    """Gradescope-format results of some catalogue tests: (key, score, output)."""
    by_key = {t.key: t for t in TESTS}
    tests = [
        {"name": by_key[k].name, "number": k, "score": s, "max_score": by_key[k].points,
         "output": out, "visibility": by_key[k].visibility}
        for k, s, out in entries
    ]  # fmt: skip
    return {"score": sum(t["score"] for t in tests), "output": "summary",
            "extra_data": {"sandbox": "bubblewrap"}, "tests": tests}  # fmt: skip


def test_hidden_tests_count_in_the_score_as_one_line_with_nothing_of_theirs():
    hidden = [t.key for t in TESTS if t.visibility != VISIBLE][:2]
    graded = _graded([("2.1", 2, "all values match"), (hidden[0], 0, "SECRET-MESSAGE"),
                      (hidden[1], 1, "SECRET-TOO")])  # fmt: skip
    results = prairielearn.to_prairielearn(graded)
    most = sum(t.points for t in TESTS if t.key in ("2.1", *hidden))
    assert results["score"] == pytest.approx(3 / most)
    assert [t["name"] for t in results["tests"]] == [
        next(t.name for t in TESTS if t.key == "2.1"),  # "2.1 ray-plane hits", once
        "Hidden tests",
    ]
    line = results["tests"][1]
    assert (line["points"], line["max_points"]) == (1, most - 2)
    assert "SECRET" not in json.dumps(results)


def test_a_picture_becomes_an_image_and_pictures_go_largest_first_past_the_limit():
    import numpy as np

    from raykit_grading.grading.results import html_output

    rng = np.random.default_rng(7)
    small = html_output("3.6 text", np.zeros((8, 8, 3), np.uint8))
    noise = html_output("3.7 text", rng.integers(0, 256, (200, 200, 3), dtype=np.uint8))
    results = prairielearn.to_prairielearn(_graded([("3.6", 4, small), ("3.7", 0, noise)]))
    assert [t["output"] for t in results["tests"]] == ["3.6 text", "3.7 text"]
    assert all(t["images"][0]["url"].startswith("data:image/png;base64,") for t in results["tests"])
    size = len(json.dumps(results))
    trimmed = prairielearn.within_limit(json.loads(json.dumps(results)), size - 1)
    assert ["images" in t for t in trimmed["tests"]] == [True, False]  # the large one went
    assert "1 feedback picture(s) left out" in trimmed["message"]


def _job(tmp_path: Path, student: dict[str, bytes] | None, seed: bool = True) -> dict:
    """run_job on a /grade folder laid out as PrairieLearn lays it out, here (no container)."""
    root = tmp_path / "grade"
    (root / "tests").mkdir(parents=True)
    if seed:
        _seed_file(root / "tests")
    if student is not None:
        (root / "student").mkdir()
        for name, data in student.items():
            (root / "student" / name).write_bytes(data)
    prairielearn.run_job(root, ["--only", "2.1"])
    return json.loads((root / "results/results.json").read_text())


def _zip_of(folder: Path, top: str = "") -> bytes:
    path = folder.parent / f"{folder.name}.zip"
    with zipfile.ZipFile(path, "w") as archive:
        for file in sorted((folder / "raykit").rglob("*.py")):
            archive.write(file, top + file.relative_to(folder).as_posix())
    return path.read_bytes()


@pytest.mark.parametrize(
    "upload, says",
    [
        (None, "nothing was submitted: upload raykit.zip"),
        ({"fib.py": b"x"}, "fib.py: not a file this question takes (it takes raykit.zip only)"),
        ({"raykit.zip": b"not a zip"}, "raykit.zip"),
        ("zip of the wrong folder", "no raykit package"),
    ],
)
def test_a_submission_in_the_wrong_shape_is_not_gradable_and_says_why(tmp_path, upload, says):
    if upload == "zip of the wrong folder":
        upload = {"raykit.zip": _zip_of(make_submission(tmp_path / "s"), "work/deep/er/still/")}
    results = _job(tmp_path, upload)
    assert results["gradable"] is False and "tests" not in results, results
    assert any(says in error for error in results["format_errors"]), results


def test_no_seed_in_the_question_is_not_graded_never_a_score(tmp_path):
    upload = {"raykit.zip": _zip_of(make_submission(tmp_path / "s"))}
    results = _job(tmp_path, upload, seed=False)
    assert results["gradable"] is False and "format_errors" not in results
    assert results["message"].startswith("NOT GRADED: the question's tests/ has no usable")


# ---- in a container, as PrairieLearn runs it ------------------------------------------------


@pytest.fixture(scope="session")
def pl_image(tmp_path_factory) -> tuple[str, Path]:
    """The image built once from what ``prairielearn -o`` writes (a fixed seed: the same code
    makes the same image), and the question's tests/ folder."""
    problem = containers.docker_problem()
    if problem:
        pytest.skip(f"the PrairieLearn lane needs Docker: {problem}")
    base = os.environ.get("RAYKIT_CONTAINER_BASE", containers.DEBIAN_BASE)
    if not containers.image_exists(base):
        pytest.skip(
            f"no base image {base} (python -m raykit_grading.platforms.containers base-image)"
        )
    folder = tmp_path_factory.mktemp("pl")
    out = prairielearn.write_course_files(folder / "pl", "course/raykit", SEED)
    try:
        built = containers.build_folder_image(out / "grader-image", base)
    except containers.ContainerError as exc:
        pytest.fail(f"the grader image does not build: {exc}")
    return built.image, out / "questions/raykit/tests"


def grade_as_prairielearn(pl_image, student: Path, tmp_path: Path, options: str = "", timeout=600):
    image, tests = pl_image
    env = {"RAYKIT_GRADE_OPTIONS": options} if options else None
    return containers.grade_in_prairielearn_container(
        image, student, tests, tmp_path / "results", prairielearn.ENTRYPOINT, timeout, env
    )


def _uploaded(submission: Path, tmp_path: Path) -> Path:
    student = tmp_path / "student"
    student.mkdir(parents=True)
    (student / "raykit.zip").write_bytes(_zip_of(submission))
    return student


@pytest.mark.slow
def test_in_the_container_an_honest_and_a_mistaken_submission_score_what_grade_scores(
    pl_image, tmp_path
):
    """Under the question's seed, every test: the solution scores full marks; a mistaken one
    scores in PrairieLearn what ``grade`` scores here, visible test for visible test."""
    total = sum(t.points for t in TESTS)
    honest = grade_as_prairielearn(
        pl_image, _uploaded(make_submission(tmp_path / "s"), tmp_path / "h"), tmp_path / "h"
    )
    assert honest.results is not None, f"{honest.problem}\n{honest.output[-3000:]}"
    assert honest.results["gradable"] is True and honest.results["score"] == 1.0, honest.results
    flipped = make_submission(tmp_path / "flipped", "rows_flipped")
    mistaken = grade_as_prairielearn(pl_image, _uploaded(flipped, tmp_path / "m"), tmp_path / "m")
    assert mistaken.results is not None, f"{mistaken.problem}\n{mistaken.output[-3000:]}"
    local_path = tmp_path / "local.json"
    local = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(flipped), "-o", str(local_path),
         "--seed", str(SEED)],
        capture_output=True, text=True, cwd=REPO, timeout=900,
    )  # fmt: skip
    assert local.returncode == 0, local.stderr[-2000:]
    here = json.loads(local_path.read_text())
    assert mistaken.results["score"] == pytest.approx(here["score"] / total, abs=1e-6)
    assert mistaken.results["score"] < 1.0
    shown = {t["name"].split()[0]: t["points"] for t in mistaken.results["tests"]}
    visible = {t["number"]: t["score"] for t in here["tests"] if t["visibility"] == VISIBLE}
    hidden = sum(t["score"] for t in here["tests"] if t["visibility"] != VISIBLE)
    assert shown == {**visible, "Hidden": pytest.approx(hidden)}
    assert any("images" in t for t in mistaken.results["tests"])  # the renders' pictures


@pytest.mark.slow
def test_in_the_container_a_wrong_shape_is_not_gradable_and_a_job_past_its_timeout_has_no_results(
    pl_image, tmp_path
):
    student = tmp_path / "student"
    student.mkdir()
    (student / "raykit.py").write_text("print('hello')\n")
    graded = grade_as_prairielearn(pl_image, student, tmp_path)
    assert graded.status == 0 and graded.results["gradable"] is False, graded.output[-2000:]
    assert graded.results["format_errors"] == [
        "raykit.py: not a file this question takes (it takes raykit.zip only)",
        "no raykit.zip: upload your raykit/ folder zipped",
    ]
    honest = _uploaded(make_submission(tmp_path / "s"), tmp_path / "h")
    stopped = grade_as_prairielearn(pl_image, honest, tmp_path / "h", timeout=3)
    assert stopped.status is None and stopped.results is None and stopped.problem == "timed out"
    gone = subprocess.run(
        ["docker", "container", "inspect", stopped.container], capture_output=True
    )
    assert gone.returncode != 0  # removed


@pytest.mark.slow
def test_the_image_holds_no_seed_and_no_hidden_scene(pl_image):
    image, _ = pl_image
    found = subprocess.run(
        ["docker", "run", "--rm", "--network", "none", "--entrypoint", "find", image, "/",
         "-xdev", "(", "-name", "grading-seed", "-o", "-name", "hidden-scenes", "-o", "-name",
         "odd.json", ")"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert found.returncode == 0 and found.stdout == "", found.stdout + found.stderr

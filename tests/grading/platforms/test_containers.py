"""The zip in a real container (:mod:`raykit_grading.platforms.containers`) and ``try-zip``, the
check an instructor runs before uploading the zip.

The hostile suite's ``container`` way (tests/grading/hostile/) grades every
attack through the same image; here: the zip laid out as Gradescope lays it out, try-zip's
scores equal to the local ``grade``'s, and try-zip without Docker in one line.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import REPO
from mistaken_submissions import make_submission
from raykit_grading.assignment.seeds import HEADER
from raykit_grading.platforms import containers
from raykit_grading.platforms.gradescope import build_zip

SEED = 20261123


def _zip(path: Path, entries: dict[str, tuple[int, bytes]]) -> Path:
    with zipfile.ZipFile(path, "w") as archive:
        for name, (mode, data) in entries.items():
            info = zipfile.ZipInfo(name)
            info.external_attr = mode << 16
            archive.writestr(info, data)
    return path


def test_the_zip_is_extracted_at_the_top_of_source_with_its_modes(tmp_path):
    archive = _zip(tmp_path / "a.zip", {
        "setup.sh": (0o755, b"#!/bin/sh\n"),
        "grading-seed": (0o600, b"1\n"),
        "raykit_grading/x.py": (0o644, b""),
    })  # fmt: skip
    containers.extract_as_gradescope(archive, tmp_path / "source")
    modes = {p.relative_to(tmp_path / "source").as_posix(): p.stat().st_mode & 0o777
             for p in (tmp_path / "source").rglob("*") if p.is_file()}  # fmt: skip
    assert modes == {"setup.sh": 0o755, "grading-seed": 0o600, "raykit_grading/x.py": 0o644}


@pytest.mark.parametrize("name", ["../evil", "/etc/evil", "a/../../evil"])
def test_a_zip_entry_outside_the_zip_is_refused(tmp_path, name):
    archive = _zip(tmp_path / "a.zip", {name: (0o644, b"x")})
    with pytest.raises(containers.ContainerError, match="outside the zip"):
        containers.extract_as_gradescope(archive, tmp_path / "source")


def test_the_image_tag_follows_the_contents_not_the_timestamps(tmp_path):
    one = _zip(tmp_path / "one.zip", {"setup.sh": (0o755, b"a"), "run_autograder": (0o755, b"b")})
    os.utime(one, (0, 0))
    two = _zip(tmp_path / "two.zip", {"setup.sh": (0o755, b"a"), "run_autograder": (0o755, b"b")})
    three = _zip(tmp_path / "3.zip", {"setup.sh": (0o755, b"a"), "run_autograder": (0o700, b"b")})
    digest = containers.zip_digest
    assert digest(one, "base") == digest(two, "base")
    assert digest(one, "base") != digest(three, "base")  # a mode is content
    assert digest(one, "base") != digest(one, "other")  # so is the base image


def test_a_zip_without_setup_sh_at_its_top_is_refused_before_any_build(tmp_path):
    """The old layout (the grader under source/) would land in /autograder/source/source."""
    archive = _zip(tmp_path / "a.zip", {
        "source/setup.sh": (0o755, b""), "source/run_autograder": (0o755, b""),
    })  # fmt: skip
    with pytest.raises(containers.ContainerError, match="at the zip's top"):
        containers.build_image(archive, "any")


def test_try_zip_without_docker_says_how_to_get_it_in_one_line(tmp_path):
    archive = build_zip(tmp_path / "autograder.zip")
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "try-zip", str(archive), str(tmp_path)],
        capture_output=True, text=True, cwd=REPO, env={"PATH": str(tmp_path)},
    )  # fmt: skip
    assert run.returncode == 2
    assert "Traceback" not in run.stderr and len(run.stderr.strip().splitlines()) == 1
    assert run.stderr.startswith("raykit_grading: error: try-zip runs the zip in Docker")
    assert "apt-get install docker.io" in run.stderr


def _base_image() -> str:
    """The base image try-zip builds on in these tests; skips saying why where there is none."""
    problem = containers.docker_problem()
    if problem:
        pytest.skip(f"try-zip needs Docker: {problem}")
    base = os.environ.get("RAYKIT_CONTAINER_BASE", containers.DEBIAN_BASE)
    if not containers.image_exists(base):
        if base != containers.DEBIAN_BASE or os.geteuid() != 0:
            pytest.skip(
                f"no base image {base} (python -m raykit_grading.platforms.containers base-image)"
            )
        try:
            containers.make_base_image(base)
        except containers.ContainerError as exc:
            pytest.skip(f"cannot make the base image {base}: {exc}")
    return base


@pytest.mark.slow
def test_try_zip_scores_what_the_local_grade_scores(tmp_path):
    """The solution and a mistaken submission, through try-zip (a fresh container each, the
    image built from the zip as Gradescope builds it), score test for test what ``grade``
    gives here under the same seed."""
    base = _base_image()
    seed_file = tmp_path / "grading-seed"
    seed_file.write_text(f"{HEADER}{SEED}\n")
    seed_file.chmod(0o600)
    archive = build_zip(tmp_path / "autograder.zip", SEED)
    submissions = [make_submission(tmp_path / "solution"),
                   make_submission(tmp_path / "flipped", "rows_flipped")]  # fmt: skip
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "try-zip", str(archive),
         *map(str, submissions), "--base-image", base, "-o", str(tmp_path / "tried")],
        capture_output=True, text=True, cwd=tmp_path, timeout=1800,
    )  # fmt: skip
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    for submission in submissions:
        line = next(li for li in run.stdout.splitlines() if li.startswith(f"{submission}: "))
        score, path = re.search(
            r": ([\d.]+) of [\d.]+ points .*results\.json: (.+)$", line
        ).groups()
        tried = json.loads(Path(path).read_text())
        assert tried["extra_data"]["sandbox"].startswith("chroot+uid+"), tried["extra_data"]
        local_path = tmp_path / f"local-{submission.name}.json"
        local = subprocess.run(
            [sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o",
             str(local_path), "--seed", str(SEED)],
            capture_output=True, text=True, cwd=REPO, timeout=900,
        )  # fmt: skip
        assert local.returncode == 0, local.stderr[-2000:]
        here = json.loads(local_path.read_text())
        assert float(score) == tried["score"] == here["score"]
        assert {t["number"]: t["score"] for t in tried["tests"]} == {
            t["number"]: t["score"] for t in here["tests"]
        }
    assert float(re.search(r"solution: ([\d.]+) of", run.stdout).group(1)) > float(
        re.search(r"flipped: ([\d.]+) of", run.stdout).group(1)
    )


@pytest.mark.slow
def test_a_zipped_submission_and_a_grading_past_the_timeout(tmp_path):
    """A submission uploaded as a zip is put into /autograder/submission as Gradescope puts it
    and graded; a grading stopped at the timeout has no results, says so, and leaves no
    container behind."""
    base = _base_image()
    image = containers.build_image(build_zip(tmp_path / "autograder.zip", SEED), base).image
    solution = make_submission(tmp_path / "solution")
    with zipfile.ZipFile(tmp_path / "work.zip", "w") as archive:
        for path in sorted((solution / "raykit").rglob("*.py")):
            archive.write(path, path.relative_to(solution).as_posix())
    options = {"RAYKIT_GRADE_OPTIONS": f"--only 2.1 --wall-seconds 4 --seed {SEED}"}
    graded = containers.grade_in_container(image, tmp_path / "work.zip", tmp_path / "a", options)
    assert graded.status == 0 and graded.results["score"] == 2, graded.output[-2000:]
    stopped = containers.grade_in_container(image, solution, tmp_path / "b", timeout=3)
    assert stopped.status is None and stopped.results is None
    assert (
        stopped.problem == "no results.json was written" and "stopped after 3 s" in stopped.output
    )
    for name in (graded.container, stopped.container):
        assert name.startswith("raykit-grade-")
        gone = subprocess.run(["docker", "container", "inspect", name], capture_output=True)
        assert gone.returncode != 0  # removed

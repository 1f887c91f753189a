"""The Gradescope autograder zip (raykit_grading.platforms.gradescope): at its top, what Gradescope
puts in /autograder/source; what its setup.sh installs exists for every base image's Python, and
grades alike.

``raykit_grading/grader-requirements.txt`` pins the grader's numpy, Pillow and tqdm. Gradescope's
base images run Python 3.10 (Ubuntu 22.04, its default) and 3.12 (Ubuntu 24.04): pip must find
a wheel of each pin for both (and for 3.11 and 3.13, Debian's and the next). And a submission
graded with those versions gets what it gets with the versions of the machine running the suite.
"""

from __future__ import annotations

import json
import subprocess
import sys
import zipfile

import pytest

from conftest import REPO
from mistaken_submissions import make_submission
from raykit_grading.platforms.gradescope import REQUIREMENTS

pytestmark = pytest.mark.slow

BASE_IMAGE_PYTHONS = ("3.10", "3.11", "3.12", "3.13")


@pytest.mark.parametrize("python_version", BASE_IMAGE_PYTHONS)
def test_every_pin_has_a_wheel_for_the_base_images_python(python_version, tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "pip", "download", "--quiet", "--no-deps",
         "--disable-pip-version-check", "--only-binary=:all:", "--python-version",
         python_version, "--platform", "manylinux_2_17_x86_64", "--platform",
         "manylinux2014_x86_64", "--platform", "manylinux_2_28_x86_64", "-r",
         str(REQUIREMENTS), "-d", str(tmp_path)],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    if run.returncode != 0 and "Could not find a version" not in run.stderr:
        pytest.skip(f"the package index cannot be reached: {run.stderr.strip()[-300:]}")
    assert run.returncode == 0, run.stderr
    pinned = [line.split("==")[0].lower() for line in REQUIREMENTS.read_text().splitlines()
              if line and not line.startswith("#")]  # fmt: skip
    wheels = sorted(p.name.lower() for p in tmp_path.glob("*.whl"))
    assert len(wheels) == len(pinned), wheels
    assert all(any(w.startswith(name) for w in wheels) for name in pinned), wheels


def test_the_pinned_versions_grade_as_this_machines_versions(grader_python, tmp_path):
    """The same submissions, seed and tests, graded with the pinned numpy and Pillow and with
    this suite's: the same results, message for message."""
    submissions = {
        "solution": make_submission(tmp_path / "solution"),
        "mistaken": make_submission(tmp_path / "mistaken", "fov_horizontal"),
    }
    only = ["1.6", "2.1", "2.3", "3.2", "3.6", "4.4"]
    for name, submission in submissions.items():
        graded = {}
        for label, python in (("pinned", grader_python), ("here", sys.executable)):
            out = tmp_path / f"{name}-{label}.json"
            run = subprocess.run(
                [python, "-m", "raykit_grading", "grade", str(submission), "-o", str(out),
                 "--seed", "20261126", "--only", *only],
                capture_output=True, text=True, timeout=600, cwd=REPO,
                env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(REPO)},
            )  # fmt: skip
            assert run.returncode == 0, run.stderr
            results = json.loads(out.read_text())
            graded[label] = [(t["number"], t["score"], t["output"]) for t in results["tests"]]
        assert graded["pinned"] == graded["here"], name


def test_the_zip_holds_at_its_top_what_gradescope_puts_in_autograder_source(tmp_path):
    """Gradescope extracts the zip into /autograder/source: setup.sh, run_autograder, the
    requirements, the seed and the grader's packages are at the zip's top, not in a folder."""
    from raykit_grading.platforms.gradescope import REQUIREMENTS, build_zip

    with zipfile.ZipFile(build_zip(tmp_path / "ag.zip")) as archive:
        setup = archive.read("setup.sh").decode()
        names = archive.namelist()
        pinned = archive.read("grader-requirements.txt")
    tops = {name.split("/", 1)[0] for name in names}
    assert tops == {"setup.sh", "run_autograder", "grader-requirements.txt", "grading-seed",
                    "raykit", "raykit_grading", "scenes", "grading"}  # fmt: skip
    assert "raykit_grading/__main__.py" in names and "grading/hidden-scenes/odd.json" in names
    assert pinned == REQUIREMENTS.read_bytes()
    assert '-r "$source/grader-requirements.txt"' in setup and "bubblewrap" in setup
    assert not any("__pycache__" in name for name in names)

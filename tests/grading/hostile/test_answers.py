"""The answers are nowhere to copy: the shipped answers do not answer the graded tests (1),
and the solution is nowhere the child can read, nor can it write outside its sandbox (6)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO
from hostile.deployed import (
    everything_visible,
    grade_as_deployed,
    scores,
    submission_wrapping,
)
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS

pytestmark = pytest.mark.slow


# ---- 1: the shipped (public) answers do not answer the graded tests --------------------------


def test_1_a_submission_that_replays_the_shipped_answers_scores_zero(release, autograder, tmp_path):
    """It implements nothing: it returns the release's expected results (and reference image)
    for any input, which passes every public test and no graded one."""
    submission = make_submission(tmp_path / "submission")
    answers = submission / "raykit" / "answers"
    for case in ("2_1", "3_6", "4_4"):
        shutil.copytree(release / "tests/expected" / case, answers / case)
    replay = (
        "import numpy as _np, pathlib as _p\n"
        "_A = _p.Path(__file__).parent / 'answers'\n"
        "def _answer(case, key):\n"
        "    with _np.load(_A / case / 'expected.npz') as data:\n"
        "        return data[key]\n"
    )
    edits = {
        "planes.py": replay + "def hit_plane(o, d, a, n):\n    return _answer('2_1', 't')",
        "shading.py": replay + "def lambert(kd, i, n, l):\n    return _answer('4_4', 'L')",
        "render.py": replay + "def render(scene, samples=1, **kw):\n"
        "    return Render(_answer('3_6', 'rgb'), None, None)",
    }
    for name, code in edits.items():
        with open(submission / "raykit" / name, "a") as module:
            module.write("\n" + code + "\n")
    nodes = [f"tests/test_visible.py::test_visible[{t.name}]" for t in TESTS
             if t.key in ("2.1", "3.6", "4.4")]  # fmt: skip
    student = subprocess.run(  # the public tests: all three pass
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *nodes],
        cwd=_release_with(release, submission, tmp_path), capture_output=True, text=True,
        env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(tmp_path / "with")},
    )  # fmt: skip
    assert "3 passed" in student.stdout, student.stdout[-1500:]
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6", "4.4"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": 0, "3.6": 0, "4.4": 0}, results


def _release_with(release: Path, submission: Path, tmp_path: Path) -> Path:
    folder = tmp_path / "with"
    shutil.copytree(release, folder)
    shutil.rmtree(folder / "raykit")
    shutil.copytree(submission / "raykit", folder / "raykit")
    return folder


# ---- 6: the solution is nowhere the child can read -----------------------------------------

SEARCH = (
    "def hit_plane(origins, directions, a, n):\n"
    "    import os, sys, importlib.util\n"
    "    found = []\n"
    "    for top, dirs, files in os.walk('/', onerror=lambda e: None):\n"
    "        dirs[:] = [d for d in dirs if d not in ('proc', 'sys', 'dev')]\n"
    "        for name in files:\n"
    "            path = os.path.join(top, name)\n"
    "            try:\n"
    "                text = open(path, errors='replace').read(200000)\n"
    "            except OSError:\n                continue\n"
    "            if 'CANARY-7f3a' in text or 'secret.txt' in name:\n"
    "                print('FOUND', path, text[:40])\n"
    "            if name == 'planes.py' and '(a - origins) @ n' in text:\n"
    "                found.append(path)\n"
    "    for path in found:\n"
    "        spec = importlib.util.spec_from_file_location('reference_planes', path)\n"
    "        module = importlib.util.module_from_spec(spec)\n"
    "        spec.loader.exec_module(module)\n"
    "        return module.hit_plane(origins, directions, a, n)\n"
    "    import numpy\n"
    "    return numpy.zeros(len(origins))\n"
)


def test_6_a_submission_that_searches_the_disk_finds_no_solution(
    release, autograder, canary, tmp_path
):
    submission = tmp_path / "submission"
    shutil.copytree(release / "raykit", submission / "raykit")
    with open(submission / "raykit/planes.py", "a") as module:
        module.write("\n" + SEARCH)
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 0}, results
    assert "CANARY" not in everything_visible(results) and "FOUND" not in everything_visible(
        results
    )


def test_6_nothing_outside_the_sandbox_is_written(release, autograder, canary, tmp_path):
    """It answers right, and on the way tries to leave files everywhere it might: they all
    stay inside its own sandbox (gone after the test), and it keeps its full score."""
    marker = f"written-by-a-submission-{os.getpid()}"
    targets = [
        f"/tmp/{marker}",
        str(canary.parent / marker),
        str(REPO / marker),
        str(autograder / "source" / marker),
        str(tmp_path / marker),
        f"/var/tmp/{marker}",
        f"/dev/shm/{marker}",
    ]
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os\n"
        f"    for path in {targets!r}:\n"
        "        try:\n            open(path, 'w').write('x')\n"
        "        except OSError:\n            pass\n"
        "    return _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert [path for path in targets if os.path.exists(path)] == []

"""Hostile and broken submissions, graded by the real grader: each scores 0, none breaks the run,
and results.json is always valid and written by the grader.

As root (as on Gradescope) they go through the autograder zip's own run_autograder in a
Gradescope-like folder layout, with the grader's source closed to the unprivileged user the
submissions run as. Not as root, they go through the grader directly, and the cheats that only
that user separation stops are skipped, saying so.
"""

import json
import os
import shutil
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import pytest

from raykit_grading.gradescope import build_zip
from raykit_grading.release import build_release

AS_ROOT = os.geteuid() == 0
NAMES = ["2.1", "3.6"]  # one array test, one image test
WALL = 4.0

# name: (file in raykit/ to append to, code, needs root). {root} is the autograder folder.
HOSTILE = {
    "infinite loop at import": ("__init__.py", "while True:\n    pass\n", False),
    "memory bomb": ("__init__.py", "hog = [bytearray(10**8) for _ in range(1000)]\n", False),
    "fork bomb": (
        "__init__.py",
        "import os\nwhile True:\n    try:\n        os.fork()\n    except OSError:\n        pass\n",
        False,
    ),
    "os._exit at import": ("__init__.py", "import os\nos._exit(0)\n", False),
    "prints 100 MB": (
        "__init__.py",
        "import sys\nfor _ in range(100):\n"
        "    sys.stdout.write('x' * 1_000_000)\nsys.stdout.flush()\n",
        False,
    ),
    "writes its own results.json": (
        "__init__.py",
        "import json\nfor path in ('{root}/results/results.json', "
        "'/autograder/results/results.json'):\n    try:\n"
        "        open(path, 'w').write(json.dumps({{'score': 1000, 'tests': []}}))\n"
        "    except OSError:\n        pass\n",
        False,
    ),
    "monkeypatches numpy and the comparison": (
        "planes.py",
        "import numpy as _np\n_np.allclose = _np.isclose = _np.array_equal = "
        "lambda *a, **k: True\n"
        "import sys as _sys\n_sys.modules['grading'] = None\n"
        "def hit_plane(origins, directions, a, n):\n    return _np.zeros(len(origins))\n",
        False,
    ),
    "wrong shape": (
        "planes.py",
        "import numpy as _np\ndef hit_plane(origins, directions, a, n):\n    return _np.zeros(3)\n",
        False,
    ),
    "strings instead of numbers": (
        "planes.py",
        "import numpy as _np\n"
        "def hit_plane(origins, directions, a, n):\n    return _np.array(['7'] * len(origins))\n",
        False,
    ),
    "NaN everywhere": (
        "render.py",
        "import numpy as _np\n"
        "def render(scene, samples=1):\n    h, w = scene.camera.height, scene.camera.width\n"
        "    return Render(_np.full((h, w, 3), _np.nan), None, None)\n",
        False,
    ),
    "reads the grader's files": (
        "planes.py",
        "import numpy as _np\ndef hit_plane(origins, directions, a, n):\n"
        "    import glob\n    found = glob.glob('{root}/source/**/*', recursive=True)\n"
        "    assert found, 'nothing readable'\n    return _np.zeros(len(origins))\n",
        True,
    ),
    "imports the reference raykit": (
        "planes.py",
        "def hit_plane(origins, directions, a, n):\n    import importlib, sys\n"
        "    for name in [m for m in sys.modules if m.startswith('raykit')]:\n"
        "        del sys.modules[name]\n"
        "    sys.path[:] = ['{root}/source', '{grader_site}'] + sys.path\n"
        "    reference = importlib.import_module('raykit.planes')\n"
        "    return reference.hit_plane(origins, directions, a, n)\n",
        True,
    ),
}


@pytest.fixture(scope="module")
def release(tmp_path_factory):
    out = tmp_path_factory.mktemp("hostile-release") / "student"
    build_release(out)
    return out


@pytest.fixture(scope="module")
def autograder(tmp_path_factory):
    """The autograder zip unpacked as Gradescope does, source closed to everyone but root."""
    root = Path("/tmp") / f"raykit-autograder-{os.getpid()}"  # outside pytest's private tmp
    shutil.rmtree(root, ignore_errors=True)
    (root / "source").mkdir(parents=True)
    archive = build_zip(tmp_path_factory.mktemp("zip") / "autograder.zip")
    with zipfile.ZipFile(archive) as opened:
        opened.extractall(root / "zipped")
    shutil.copytree(root / "zipped/source", root / "source", dirs_exist_ok=True)
    shutil.copy(root / "zipped/run_autograder", root / "run_autograder")
    os.chmod(root, 0o755)
    os.chmod(root / "source", 0o700)
    yield root
    shutil.rmtree(root, ignore_errors=True)


def run_autograder(root: Path, submission: Path, child_python: str, options: str) -> dict:
    shutil.rmtree(root / "submission", ignore_errors=True)
    shutil.rmtree(root / "results", ignore_errors=True)
    shutil.copytree(submission, root / "submission")
    env = {
        "PATH": "/usr/bin:/bin",
        "AUTOGRADER_ROOT": str(root),
        "RAYKIT_GRADER_PYTHON": sys.executable,
        "RAYKIT_CHILD_PYTHON": child_python,
        "RAYKIT_GRADE_OPTIONS": options,
    }
    run = subprocess.run(
        ["bash", str(root / "run_autograder")], env=env, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads((root / "results/results.json").read_text())


@pytest.mark.parametrize("name", sorted(HOSTILE))
def test_hostile_submission_scores_zero_and_the_run_survives(
    name, release, autograder, child_python, tmp_path
):
    file, code, needs_root = HOSTILE[name]
    if needs_root and not AS_ROOT:
        pytest.skip("only the unprivileged sandbox user (grading as root) stops this cheat")
    submission = tmp_path / "submission"
    shutil.copytree(release / "raykit", submission / "raykit")
    import sysconfig

    grader_site = sysconfig.get_paths()["purelib"]  # where the grader's own raykit is installed
    with open(submission / "raykit" / file, "a") as module:
        module.write("\n" + code.format(root=autograder, grader_site=grader_site))
    start = time.perf_counter()
    if AS_ROOT:
        results = run_autograder(
            autograder, submission, child_python, f"--only {' '.join(NAMES)} --wall-seconds {WALL}"
        )
    else:
        from raykit_grading.grade import grade_to_file
        from raykit_grading.sandbox import Limits

        out = tmp_path / "results.json"
        grade_to_file(
            submission,
            out,
            child_python=child_python,
            names=NAMES,
            limits=Limits(wall_seconds=WALL, cpu_seconds=int(WALL) + 1),
        )
        results = json.loads(out.read_text())
    seconds = time.perf_counter() - start
    assert [t["name"].split()[0] for t in results["tests"]] == NAMES
    assert results["score"] == 0, results
    assert all(t["score"] == 0 for t in results["tests"])
    assert seconds < len(NAMES) * (WALL + 10)
    assert all(len(t["output"]) <= 4000 for t in results["tests"])


def test_a_correct_submission_through_run_autograder_scores_full_marks(
    autograder, child_python, tmp_path
):
    if not AS_ROOT:
        pytest.skip("run_autograder is exercised as root, as Gradescope runs it")
    from mistaken_submissions import make_submission

    from raykit_grading.catalog import TESTS

    results = run_autograder(autograder, make_submission(tmp_path), child_python, "")
    assert results["score"] == pytest.approx(sum(t.points for t in TESTS))


def test_no_sandbox_user_process_outlives_the_run():
    if not AS_ROOT:
        pytest.skip("processes are counted per sandbox user, which exists when grading as root")
    from raykit_grading.sandbox import SANDBOX_UIDS

    uids = set(SANDBOX_UIDS)
    left = [p for p in Path("/proc").iterdir() if p.name.isdigit() and p.stat().st_uid in uids]
    assert left == []

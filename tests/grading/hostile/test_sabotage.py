"""The old kinds of sabotage (loops, memory, forks, printing, monkeypatching, garbage
arrays), a process left holding the test's output, one broken test (4), a slow submission:
each costs only what it sabotages, and the run survives."""

from __future__ import annotations

import os
import re

import pytest

from hostile.deployed import (
    POINTS,
    grade_as_deployed,
    processes_naming,
    scores,
    submission_with,
)
from mistaken_submissions import make_submission

pytestmark = pytest.mark.slow


# ---- the old kinds: each scores 0 on the tests it sabotages, and the run survives ----------

SABOTAGE = {
    "infinite loop at import": ("__init__.py", "while True:\n    pass"),
    "memory bomb": ("__init__.py", "hog = [bytearray(10**8) for _ in range(1000)]"),
    "fork bomb": (
        "__init__.py",
        "import os\nwhile True:\n    try:\n        os.fork()\n    except OSError:\n        pass",
    ),
    "os._exit at import": ("__init__.py", "import os\nos._exit(0)"),
    "prints 100 MB": (
        "__init__.py",
        "import sys\nfor _ in range(100):\n    sys.stdout.write('x' * 1_000_000)\n"
        "sys.stdout.flush()",
    ),
    "monkeypatches numpy and the comparison": (
        "planes.py",
        "import numpy as _np\n_np.allclose = _np.isclose = _np.array_equal = "
        "lambda *a, **k: True\nimport sys as _sys\n_sys.modules['raykit_grading'] = None\n"
        "def hit_plane(origins, directions, a, n):\n    return _np.zeros(len(origins))",
    ),
    "wrong shape": (
        "planes.py",
        "import numpy as _np\ndef hit_plane(origins, directions, a, n):\n    return _np.zeros(3)",
    ),
    "strings instead of numbers": (
        "planes.py",
        "import numpy as _np\ndef hit_plane(origins, directions, a, n):\n"
        "    return _np.array(['7'] * len(origins))",
    ),
    "NaN everywhere": (
        "render.py",
        "import numpy as _np\ndef render(scene, samples=1, **kw):\n"
        "    h, w = scene.camera.height, scene.camera.width\n"
        "    return Render(_np.full((h, w, 3), _np.nan), None, None)",
    ),
}


def test_a_process_left_holding_the_tests_output_costs_the_test_nothing(
    release, autograder, tmp_path
):
    """Importing raykit tries to start a process that would keep the test's output pipes
    open and sleep (a test is one process: the fork is refused, and the import goes on): the
    test is graded when its own code is done, not when pipes close, and no such process is
    left."""
    marker = f"HOLDER-{os.getpid()}"
    code = (
        "import os as _os, sys as _sys\n"
        "try:\n    _pid = _os.fork()\nexcept OSError:\n    _pid = -1\n"
        "if _pid == 0:\n"
        f"    _os.execv(_sys.executable, [_sys.executable, '-c', 'import time; time.sleep(60)', "
        f"'{marker}'])\n"
    )
    submission = submission_with(release, tmp_path, {"__init__.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": 2, "3.6": 4}, results
    assert processes_naming(marker) == []
    honest = make_submission(tmp_path / "honest" / "submission")  # the next student
    results, run = grade_as_deployed(
        autograder, honest, ["2.1", "3.6"], tmp_path / "honest", wall=None
    )
    assert run.returncode == 0 and scores(results) == {"2.1": 2, "3.6": 4}, results


@pytest.mark.parametrize("name", sorted(SABOTAGE))
def test_sabotage_scores_zero_and_the_run_survives(name, release, autograder, tmp_path):
    file, code = SABOTAGE[name]
    submission = submission_with(release, tmp_path, {file: code})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    # the solution with one module sabotaged: what needs that module scores nothing
    expected = {"2.1": 2, "3.6": 0} if file == "render.py" else {"2.1": 0, "3.6": 0}
    if name == "prints 100 MB":  # printing is no mistake: the output is cut, the code graded
        expected = {"2.1": 2, "3.6": 4}
    assert scores(results) == expected, results
    text = [re.sub(r"<img [^>]*>", "", t["output"]) for t in results["tests"]]
    assert all(len(output) <= 5000 for output in text)  # the printing is cut


# ---- 4: one broken test is that test's alone -----------------------------------------------


def test_4_a_test_that_kills_its_own_child_costs_only_that_test(release, autograder, tmp_path):
    code = "def hit_plane(origins, directions, a, n):\n    import os\n    os._exit(3)"
    submission = submission_with(release, tmp_path, {"planes.py": code})
    only = ["2.1", "2.3", "3.1", "4.1"]
    results, run = grade_as_deployed(autograder, submission, only, tmp_path)
    assert scores(results) == {"2.1": 0, "2.3": 2, "3.1": 1, "4.1": 1}, results
    assert results["score"] == sum(POINTS[k] for k in only) - POINTS["2.1"]


def test_a_slow_submission_is_stopped_by_the_total_budget(release, autograder, tmp_path):
    """It sleeps at import: every test times out until the total is used up, then the rest
    are not run: at most the two tests that 6 s of 4 s tests can start are run."""
    submission = submission_with(release, tmp_path, {"__init__.py": "import time\ntime.sleep(60)"})
    only = ["2.1", "2.3", "3.1", "4.1", "4.6"]
    results, run = grade_as_deployed(
        autograder, submission, only, tmp_path, extra="--total-seconds 6"
    )
    assert all(score == 0 for score in scores(results).values())
    not_run = ["not run: all tests together" in t["output"] for t in results["tests"]]
    assert sum(not_run) >= len(only) - 2, results

"""The tasks a grading test runs (raykit_grading.kit.tasks): every test's task and its callees'
is one; loaded by its path as the sandbox's child loads it, they run whichever raykit comes
first on the path, the submission's; the imports task says which of its modules do not import
and where, and stops everything when nothing can be tested."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

from raykit_grading.assignment.catalog import TESTS
from raykit_grading.kit import tasks
from raykit_grading.kit.tasks import IMPORTED, TASKS

# the child's path: the submission, then numpy (python -I -S, as raykit_grading.inside.child)
RUN_TASKS = """
import json, sys, importlib.util
submission, site, tasks_py = sys.argv[1:4]
sys.path[:0] = [submission, site]
spec = importlib.util.spec_from_file_location("tasks", tasks_py)
tasks = importlib.util.module_from_spec(spec)
spec.loader.exec_module(tasks)
import numpy as np
said = {}
try:
    said["imports"] = tasks.TASKS["imports"]({}, {})["imports"].tolist()
except Exception as exc:
    said["imports"] = f"raised {type(exc).__name__}: {exc}"
if isinstance(said["imports"], list) and said["imports"][tasks.IMPORTED.index("raykit.planes")]:
    ray = {k: np.ones((2, 3)) for k in ("origins", "directions")}
    said["t"] = tasks.TASKS["hit_plane"]({}, {**ray, "a": np.zeros(3), "n": np.ones(3)})["t"]
    said["t"] = said["t"].tolist()
print(json.dumps(said))
"""


def _submission(folder: Path, source: dict[str, str]) -> Path:
    """A raykit with every module the tasks import, empty unless ``source`` says otherwise."""
    for name in IMPORTED:
        *packages, module = name.split(".")
        for depth in range(1, len(packages) + 1):
            init = folder.joinpath(*packages[:depth], "__init__.py")
            init.parent.mkdir(parents=True, exist_ok=True)
            init.touch()
        path = folder.joinpath(*packages, f"{module}.py")
        if any(other.startswith(f"{name}.") for other in IMPORTED):  # a package
            path = folder.joinpath(*packages, module, "__init__.py")
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(source.get(name, ""))
    return folder


def _run_tasks(submission: Path) -> tuple[list[str], dict]:
    """(the lines the tasks printed, what they returned) in a fresh Python."""
    run = subprocess.run(
        [sys.executable, "-I", "-S", "-c", RUN_TASKS, str(submission),
         str(Path(np.__file__).parents[1]), tasks.__file__],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    *printed, said = run.stdout.splitlines()
    return printed, json.loads(said)


def test_every_task_a_grading_test_or_its_callees_run_is_a_task():
    named = {t.task for t in TESTS} | {c.task for t in TESTS for c in t.callees}
    assert named <= set(TASKS), named - set(TASKS)
    assert all(f.__name__ == f"task_{name}" for name, f in TASKS.items())


def test_the_tasks_run_the_submissions_raykit_and_say_which_module_does_not_import(tmp_path):
    planes = (
        "import numpy as np\n\n\ndef hit_plane(origins, directions, a, n):\n"
        "    return np.full(len(origins), 42.0)\n"
    )
    submission = _submission(
        tmp_path / "submission",
        {"raykit.planes": planes, "raykit.mirrors": "x = 1\ndef broken(:\n"},
    )
    printed, said = _run_tasks(submission)
    assert printed == ["import failed: SyntaxError: invalid syntax (in raykit/mirrors.py, line 2)"]
    assert said["imports"] == [float(name != "raykit.mirrors") for name in IMPORTED]
    assert said["t"] == [42.0, 42.0]  # the submission's hit_plane, not the reference's


def test_a_package_that_does_not_import_or_no_module_that_imports_stops_every_test(tmp_path):
    package = {"raykit": "raise RuntimeError('half written')\n"}
    printed, said = _run_tasks(_submission(tmp_path / "one/submission", package))
    assert (printed, said) == ([], {"imports": "raised RuntimeError: half written"})
    modules = {name: f"raise ValueError({name!r})\n" for name in IMPORTED[1:]}
    printed, said = _run_tasks(_submission(tmp_path / "all/submission", modules))
    first = IMPORTED[1]
    assert said == {"imports": f"raised ValueError: {first}"}  # the first one's error
    assert len(printed) == len(IMPORTED) - 1
    assert printed[0] == f"import failed: ValueError: {first} (in raykit/billboards.py, line 1)"

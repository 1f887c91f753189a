"""What runs inside the sandbox (raykit_grading.inside.child), outside any sandbox here: its
work folder laid out as the sandbox lays it out, with no uid to drop to; the task's arrays
written as an .npz to the pipe it is given and nothing to its folder, and a failing task's
traceback told in the submission's frames only, exit status 1."""

from __future__ import annotations

import importlib.util
import io
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

from raykit_grading.inside import child
from raykit_grading.sandbox.base import CHILD_SCRIPT, TASKS_SCRIPT

HIT_PLANE = """import numpy as np


def hit_plane(origins, directions, a, n):
    return _along(origins, directions) + a[0] * n[0]


def _along(origins, directions):
    return origins[:, 0] * directions[:, 1]
"""
FAILS = HIT_PLANE.replace("* directions[:, 1]", "* (1 / 0)")  # raised in _along


def _work(folder: Path, planes: str, arrays: dict, fd: int) -> Path:
    """A task's work folder: the child, the tasks, the submission, the order and its inputs."""
    folder.mkdir()
    shutil.copyfile(CHILD_SCRIPT, folder / "child.py")
    shutil.copyfile(TASKS_SCRIPT, folder / "tasks.py")
    (folder / "submission/raykit").mkdir(parents=True)
    (folder / "submission/raykit/__init__.py").write_text("")
    (folder / "submission/raykit/planes.py").write_text(planes)
    np.savez(folder / "inputs.npz", **arrays)
    order = {"task": "hit_plane", "spec": {}, "outputs_fd": fd,
             "library_paths": [str(Path(np.__file__).parents[1])]}  # fmt: skip
    (folder / "task.json").write_text(json.dumps(order))
    return folder


def _run_child(folder: Path, planes: str, arrays: dict):
    """(the finished child, what it wrote to its pipe, its folder's files before and after)."""
    read, write = os.pipe()
    try:
        work = _work(folder, planes, arrays, write)
        before = sorted(p.relative_to(work) for p in work.rglob("*"))
        ran = subprocess.run(
            [sys.executable, "-I", "-S", "-B", str(work / "child.py"), str(work)],
            capture_output=True, text=True, timeout=60, pass_fds=(write,),
        )  # fmt: skip
    finally:
        os.close(write)
    with os.fdopen(read, "rb") as pipe:
        returned = pipe.read()
    return ran, returned, before, sorted(p.relative_to(work) for p in work.rglob("*"))


def _arrays() -> dict:
    rng = np.random.default_rng(58)
    return {"origins": rng.normal(size=(6, 3)), "directions": rng.normal(size=(6, 3)),
            "a": rng.normal(size=3), "n": rng.normal(size=3)}  # fmt: skip


def test_the_child_writes_the_tasks_arrays_to_its_pipe_and_nothing_to_its_folder(tmp_path):
    arrays = _arrays()
    ran, returned, before, after = _run_child(tmp_path / "work", HIT_PLANE, arrays)
    assert (ran.returncode, ran.stderr) == (0, "")
    assert returned.startswith(b"PK")  # an .npz: a zip
    with np.load(io.BytesIO(returned), allow_pickle=False) as results:
        assert results.files == ["t"]
        along = arrays["origins"][:, 0] * arrays["directions"][:, 1]
        assert np.array_equal(results["t"], along + arrays["a"][0] * arrays["n"][0])
    assert after == before


def test_a_failing_task_exits_1_its_traceback_in_the_submissions_frames_only(tmp_path):
    ran, returned, _, _ = _run_child(tmp_path / "work", FAILS, _arrays())
    assert ran.returncode == 1 and returned == b""
    planes = f'File "{tmp_path}/work/submission/raykit/planes.py", line '
    assert ran.stderr.startswith("Traceback (most recent call last):\n")
    assert ran.stderr.count(planes) == 2  # hit_plane, then _along
    assert ran.stderr.endswith("ZeroDivisionError: division by zero\n")
    assert "child.py" not in ran.stderr and "tasks.py" not in ran.stderr


def test_say_keeps_the_submissions_frames_of_the_error_and_of_its_cause(tmp_path, capsys):
    """An error raised in the grader's frames from one in the submission's (what a task that
    checks the submission's results would raise): each part says only the submission's."""
    source = tmp_path / "submission/raykit/planes.py"
    source.parent.mkdir(parents=True)
    source.write_text(FAILS)
    spec = importlib.util.spec_from_file_location("submitted_planes", source)
    planes = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(planes)
    one = np.ones((1, 3))
    try:
        try:
            planes.hit_plane(one, one, one[0], one[0])
        except ZeroDivisionError as exc:
            raise ValueError("not arrays") from exc
    except ValueError as exc:
        child._say(exc, str(tmp_path / "submission"))
    said = capsys.readouterr().err
    assert said.count(f'File "{source}", line ') == 2
    assert said.index("ZeroDivisionError") < said.index("direct cause") < said.index("ValueError")
    assert said.endswith("ValueError: not arrays\n")
    assert __file__ not in said  # this test's frames, the grader's here

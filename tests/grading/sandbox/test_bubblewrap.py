"""The bubblewrap sandbox (raykit_grading.sandbox.bubblewrap): the limits its child is started
under, seen from a child started with them here; what bwrap is given, from files its child's
/proc cannot show; and a submission's task run in it, under those limits, as root as a uid of
its own."""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import sysconfig
import types

import numpy as np
import pytest

from conftest import AS_ROOT
from raykit_grading.grading.submissions import stage
from raykit_grading.sandbox import bubblewrap
from raykit_grading.sandbox.base import Limits, TaskFolder
from raykit_grading.sandbox.bubblewrap import Bubblewrap
from raykit_grading.sandbox.budgets import SIGNALS_PENDING
from raykit_grading.sandbox.isolation import (
    SANDBOX_UIDS,
    WORK,
    ChildPython,
    IsolationUnavailable,
    sandbox_arguments,
)
from raykit_grading.sandbox.workspace import Workspace

MB = 2**20
LIMITS = Limits(cpu_seconds=7, memory_bytes=1536 * MB, file_bytes=5 * MB, open_files=40)
NAMES = ("CPU", "AS", "FSIZE", "CORE", "NOFILE", "SIGPENDING", "NPROC")
SAID = f"""
import json, os, resource
limits = {{n: resource.getrlimit(getattr(resource, "RLIMIT_" + n)) for n in {NAMES!r}}}
adj = open("/proc/self/oom_score_adj").read().strip()
print(json.dumps({{**limits, "leads its session": os.getsid(0) == os.getpid(), "oom": adj}}))
"""


def _unprobed(as_root: bool) -> Bubblewrap:
    """A Bubblewrap as far as its child's start reads one, made without probing a Python or
    leasing uids (never run here: only its methods are)."""
    box = Bubblewrap.__new__(Bubblewrap)
    box.limits, box.as_root = LIMITS, as_root
    return box


def _limited(as_root: bool) -> dict:
    """What a child started with the sandbox's limits says of them."""
    run = subprocess.run(
        [sys.executable, "-I", "-c", SAID],
        capture_output=True, text=True, timeout=60, preexec_fn=_unprobed(as_root)._limit,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def test_the_child_starts_in_a_session_of_its_own_first_to_go_under_the_tasks_limits():
    said = _limited(as_root=True)
    assert said == {
        "CPU": [7, 7], "AS": [1536 * MB] * 2, "FSIZE": [5 * MB] * 2, "CORE": [0, 0],
        "NOFILE": [40, 40], "SIGPENDING": [SIGNALS_PENDING] * 2, "NPROC": [16, 16],
        "leads its session": True, "oom": "1000",
    }  # fmt: skip


class _NoHardLimitOfProcesses:
    """The resource module as a user with no hard limit of processes sees it (as in a
    container started with none), for a child forked from this test."""

    def __getattr__(self, name: str):
        return getattr(resource, name)

    @staticmethod
    def getrlimit(which: int) -> tuple[int, int]:
        if which == resource.RLIMIT_NPROC:
            return resource.RLIM_INFINITY, resource.RLIM_INFINITY
        return resource.getrlimit(which)


def test_a_normal_users_child_may_run_its_processes_beside_the_users_under_any_hard_limit(
    monkeypatch,
):
    """Processes count per user: a normal user's child gets room for the task's 16 besides
    the user's own (a cap below this user's own limit), and such a cap where the user has no
    limit at all."""
    here = resource.getrlimit(resource.RLIMIT_NPROC)[1]
    for unlimited in (False, True):
        if unlimited:
            monkeypatch.setattr(bubblewrap, "resource", _NoHardLimitOfProcesses())
        soft, hard = _limited(as_root=False)["NPROC"]
        assert 16 < soft == hard and (soft < here or here == resource.RLIM_INFINITY), unlimited


def test_bwrap_reads_its_arguments_and_seccomp_program_from_files_it_alone_is_given(
    tmp_path, monkeypatch
):
    box = _unprobed(as_root=False)
    box.bwrap = "/usr/bin/bwrap"  # never run: Popen below is this test's
    box.python = ChildPython(sys.executable, sysconfig.get_paths()["stdlib"], (), ())
    box.submission = tmp_path / "submission"
    box.seccomp = bytes(range(64))  # what seccomp_filter() made, as it is
    started = {}

    def popen(command, **options):
        given = os.pread(int(command[2]), 1 << 20, 0)
        seccomp = int(given.split(b"\0")[-2])
        started.update(command=command, arguments=given, options=options, seccomp=seccomp,
                       program=os.pread(seccomp, 1 << 10, 0))  # fmt: skip
        return types.SimpleNamespace(pid=0)

    monkeypatch.setattr(bubblewrap, "subprocess", types.SimpleNamespace(
        Popen=popen, DEVNULL=subprocess.DEVNULL, PIPE=subprocess.PIPE))  # fmt: skip
    folder = TaskFolder(tmp_path / "task", WORK, lambda: None)
    returned_read, returned_write = os.pipe()
    _, printed_read = box._start(folder, returned_write, None)

    command, options = started["command"], started["options"]
    arguments = command[2]
    assert command == [box.bwrap, "--args", arguments,
                       sys.executable, "-I", "-S", "-B", f"{WORK}/child.py", WORK]  # fmt: skip
    listed = sandbox_arguments(box.python, folder.path, box.submission, False)
    listed += ["--seccomp", str(started["seccomp"])]
    assert started["arguments"] == b"\0".join(a.encode() for a in listed) + b"\0"
    assert started["program"] == box.seccomp
    assert options["pass_fds"] == (returned_write, int(arguments), started["seccomp"])
    assert options["env"] == {"PATH": "/usr/bin:/bin"} and options["stdin"] == subprocess.DEVNULL
    assert options["stdout"] == options["stderr"] and options["preexec_fn"] == box._limit
    os.set_blocking(printed_read, False)
    assert os.read(printed_read, 1) == b""  # the grader keeps no end to write what it prints
    for fd in (printed_read, returned_read, returned_write):
        os.close(fd)


PLANES = """import os, resource

import numpy as np


def hit_plane(origins, directions, a, n):
    names = ("CPU", "AS", "FSIZE", "CORE", "NOFILE", "NPROC")
    said = [resource.getrlimit(getattr(resource, "RLIMIT_" + n))[0] for n in names]
    return np.array([*said, os.getuid()], float)
"""


@pytest.mark.slow
def test_a_task_runs_in_bubblewrap_under_its_limits_and_as_root_as_a_uid_of_its_own(
    tmp_path, child_python
):
    submitted = tmp_path / "submitted/raykit"
    submitted.mkdir(parents=True)
    (submitted / "__init__.py").write_text("")
    (submitted / "planes.py").write_text(PLANES)
    ray = {k: np.ones((1, 3)) for k in ("origins", "directions", "n")}
    with Workspace(tmp_path) as workspace:
        staged = stage(submitted.parent, workspace / "submission")
        box = Bubblewrap(staged.root, workspace, child_python, LIMITS)
        try:
            box.check()
        except IsolationUnavailable as exc:
            pytest.skip(str(exc))
        ran = box.run("hit_plane", {}, {**ray, "a": np.zeros(3)})
    assert ran.problem == "", ran.output
    *limits, processes, uid = ran.outputs["t"].tolist()
    assert limits == [7, box.limits.memory_bytes, 5 * MB, 0, 40]
    if AS_ROOT:
        assert processes == 16 and uid in SANDBOX_UIDS
    else:
        assert processes > 16 and uid == os.getuid()

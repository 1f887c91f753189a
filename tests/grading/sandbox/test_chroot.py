"""The chroot sandbox (raykit_grading.sandbox.chroot), made as root and under Docker's
confinement (emulated by tests/support/docker_confinement.py, whose emulation is checked here)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from conftest import AS_ROOT, REPO
from raykit_grading.sandbox.confine import landlock_abi
from raykit_grading.sandbox.isolation import SANDBOX_UIDS

EMULATION = REPO / "tests" / "support" / "docker_confinement.py"


def _emulated(command: list[str], memory_mb: int | None = 768, **kw) -> subprocess.CompletedProcess:
    """``command`` as root under Docker's default confinement (tests/support/docker_confinement.py);
    skips, saying why, where this machine cannot make it."""
    if not AS_ROOT:
        pytest.skip("emulating Docker's confinement needs root")
    memory = ["--memory-mb", str(memory_mb)] if memory_mb else []
    run = subprocess.run([sys.executable, str(EMULATION), *memory, "--", *command],
                         capture_output=True, text=True, timeout=600, **kw)  # fmt: skip
    if run.returncode == 77:
        pytest.skip(run.stderr.strip())
    return run


def test_the_docker_emulation_keeps_dockers_14_capabilities_and_refuses_namespaces():
    run = _emulated(
        [
            "bash",
            "-c",
            "grep CapEff /proc/self/status; grep memory /proc/self/cgroup;"
            "unshare --user true || echo REFUSED; bwrap --ro-bind / / true || echo NO-BWRAP",
        ]
    )
    from docker_confinement import DOCKER_CAPABILITIES

    mask = sum(1 << cap for cap in DOCKER_CAPABILITIES.values())
    assert f"CapEff:\t{mask:016x}" in run.stdout
    assert "raykit-docker-" in run.stdout  # in a memory cgroup of its own
    assert "REFUSED" in run.stdout and "NO-BWRAP" in run.stdout
    assert "Operation not permitted" in run.stderr


FACTS = """
import ctypes, errno, json, os, socket
import numpy as np
def plane_side(p, a, n):
    libc = ctypes.CDLL(None, use_errno=True)
    facts = {"uid": os.getuid(), "gid": os.getgid(), "groups": os.getgroups()}
    facts["no_new_privs"] = libc.prctl(39, 0, 0, 0, 0)
    facts["seccomp"] = libc.prctl(21, 0, 0, 0, 0)
    header, data = (ctypes.c_uint32 * 2)(0x20080522, 0), (ctypes.c_uint32 * 6)()
    libc.capget(header, data)
    facts["capabilities"] = list(data)
    def tried(action):
        try:
            action()
            return "yes"
        except OSError as exc:
            return errno.errorcode[exc.errno]
    facts["list /"] = tried(lambda: os.listdir("/"))
    facts["list /tasks"] = tried(lambda: os.listdir("/tasks"))
    facts["read /proc"] = tried(lambda: open("/proc/1/cmdline").read())
    facts["write here"] = tried(lambda: open("x", "w").close())
    facts["write tmp"] = tried(lambda: open(os.environ["TMPDIR"] + "/x", "w").close())
    facts["inet"] = tried(lambda: socket.socket())
    facts["signal 1"] = tried(lambda: os.kill(1, 0))
    facts["signal parent"] = tried(lambda: os.kill(os.getppid(), 0))
    print("FACTS", json.dumps(facts))
    return np.zeros(len(p))
"""


CHROOT_RUN = """
import json, os, sys, tempfile
from pathlib import Path
sys.path.insert(0, {repo!r})
import numpy as np
from raykit_grading.sandbox.kinds import choose_sandbox
from raykit_grading.sandbox.workspace import Workspace
with Workspace() as workspace:
    sandbox = choose_sandbox(Path({submission!r}), workspace, kind={kind!r})
    ran = sandbox.run("plane_side", {{}}, {{k: np.zeros((2, 3)) for k in ("p", "a", "n")}})
    print(sandbox.description, ran.problem)
    print(ran.output)
"""


@pytest.mark.parametrize("where", ["root", "docker"])
def test_the_chroot_childs_uid_capabilities_files_network_and_signals(where, tmp_path):
    """Its own uid (no groups, no capability, no new privileges), the seccomp filter, a tree
    with nothing of the grader's (no /proc, no other test's folder), writing only its tmp, no
    network, no signal to anything outside."""
    if not AS_ROOT:
        pytest.skip("the chroot sandbox is made by root")
    submission = tmp_path / "submission"
    (submission / "raykit").mkdir(parents=True)
    (submission / "raykit/__init__.py").write_text("")
    (submission / "raykit/planes.py").write_text(FACTS)
    os.chmod(tmp_path, 0o755)
    script = CHROOT_RUN.format(repo=str(REPO), submission=str(submission), kind="chroot")
    command = [sys.executable, "-c", script]
    run = _emulated(command) if where == "docker" else subprocess.run(
        command, capture_output=True, text=True, timeout=600)  # fmt: skip
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.startswith("chroot+uid+"), run.stdout
    facts = json.loads(run.stdout.split("FACTS ", 1)[1].splitlines()[0])
    assert facts.pop("uid") in SANDBOX_UIDS and facts.pop("gid") in SANDBOX_UIDS
    assert facts == {
        "groups": [], "no_new_privs": 1, "seccomp": 2, "capabilities": [0] * 6,
        "list /": "EACCES" if landlock_abi() else "yes", "list /tasks": "EACCES",
        "read /proc": "ENOENT", "write here": "EACCES", "write tmp": "yes",
        "inet": "EPERM", "signal 1": "EPERM", "signal parent": "EPERM",
    }  # fmt: skip

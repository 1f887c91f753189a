"""The bubblewrap sandbox's pieces (raykit_grading.sandbox.isolation): uid leases, the seccomp
filter."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from conftest import AS_ROOT, REPO
from raykit_grading.sandbox import isolation
from raykit_grading.sandbox.isolation import UidPool, kill_uid


@pytest.mark.skipif(not AS_ROOT, reason="sandbox uids are leased only when grading as root")
def test_two_graders_never_lease_the_same_uid(tmp_path):
    locks = tmp_path / "uids"
    first, second = UidPool(range(61000, 61003), locks), UidPool(range(61000, 61003), locks)
    leases = [first.lease(), second.lease(), first.lease()]
    assert len({lease.uid for lease in leases}) == 3
    with pytest.raises(RuntimeError, match="all 3 sandbox uids are in use"):
        second.lease()
    leases[1].release()
    assert second.lease().uid == leases[1].uid


def _unreaped_process_of(uid: int, reap_after: float) -> subprocess.Popen:
    """A process of ``uid`` that, once killed, stays in /proc as a zombie until this test
    reaps it, ``reap_after`` seconds from now (as a process slow to die would)."""
    child = subprocess.Popen(["sleep", "60"], user=uid, group=uid)
    threading.Timer(reap_after, child.wait).start()
    return child


@pytest.mark.skipif(not AS_ROOT, reason="sandbox uids are leased only when grading as root")
def test_a_uid_is_given_back_only_once_its_processes_have_left_proc():
    child = _unreaped_process_of(61010, reap_after=0.5)
    kill_uid(61010)
    assert child.returncode == -9 and not Path(f"/proc/{child.pid}").exists()


@pytest.mark.skipif(not AS_ROOT, reason="sandbox uids are leased only when grading as root")
def test_processes_that_outlast_the_kill_wait_are_reported(monkeypatch, capfd):
    monkeypatch.setattr(isolation, "KILL_WAIT_SECONDS", 0.2)
    child = _unreaped_process_of(61011, reap_after=1.0)
    kill_uid(61011)
    assert f"sandbox uid 61011 still has processes ['{child.pid}']" in capfd.readouterr().err
    child.wait()


# ---- the seccomp filter, as a sandbox's child has it installed ------------------------------


SECCOMP_PROBE = """
import ctypes, errno, fcntl, json, os, select, socket, sys, tempfile, threading
sys.path.insert(0, {repo!r})
from raykit_grading.sandbox.confine import install_seccomp, no_new_privileges
from raykit_grading.sandbox.isolation import CLONE_CALLS, SECCOMP_ARCHES, seccomp_filter
import platform
calls = SECCOMP_ARCHES[platform.machine()][1]
no_new_privileges()
install_seccomp(seccomp_filter())
libc = ctypes.CDLL(None, use_errno=True)
said = {{}}


def said_of(name, action):
    try:
        action()
        said[name] = "made"
    except OSError as exc:
        said[name] = errno.errorcode[exc.errno]


for name, family in (("inet", socket.AF_INET), ("inet6", socket.AF_INET6),
                     ("netlink", socket.AF_NETLINK), ("unix", socket.AF_UNIX)):
    said_of(name, lambda: socket.socket(family, socket.SOCK_DGRAM).close())
said_of("socketpair", socket.socketpair)
for name in ("keyctl", "ptrace", "unshare", "bpf", "shmget", "mq_open", "fsopen", "memfd_create",
             "inotify_init1", "fanotify_init", "io_setup"):
    libc.syscall(calls[name], 0, 0, 0, 0)
    said[name] = errno.errorcode.get(ctypes.get_errno(), "none")
said_of("epoll", lambda: select.epoll().close())
clone, clone3 = CLONE_CALLS[platform.machine()]
for name, flags in (("clone_newuser", 0x10000000), ("clone_newns", 0x00020000), ("fork", 0),
                    ("vfork", 0x4000 | 0x100)):
    ctypes.set_errno(0)
    pid = libc.syscall(clone, flags | 17, 0, 0, 0, 0)  # SIGCHLD
    if pid == 0:
        os._exit(0)
    said[name] = "made" if pid > 0 else errno.errorcode.get(ctypes.get_errno(), "none")
    if pid > 0:
        os.waitpid(pid, 0)
libc.syscall(clone3, None, 0)
said["clone3"] = errno.errorcode.get(ctypes.get_errno(), "none")
ran = []
thread = threading.Thread(target=lambda: ran.append(1))
thread.start()
thread.join()
said["thread"] = "made" if ran else "none"
said_of("O_TMPFILE", lambda: os.close(os.open("/tmp", os.O_TMPFILE | os.O_RDWR, 0o600)))
said_of("TemporaryFile", lambda: tempfile.TemporaryFile(dir="/tmp").close())
read, write = os.pipe()
said_of("pipe bigger", lambda: fcntl.fcntl(write, 1031, 2**20))  # F_SETPIPE_SZ
said_of("record lock", lambda: fcntl.lockf(tempfile.TemporaryFile(dir="/tmp"), fcntl.LOCK_EX))
said_of("flock", lambda: fcntl.flock(tempfile.TemporaryFile(dir="/tmp"), fcntl.LOCK_EX))
print(json.dumps(said))
"""


def test_the_seccomp_filter_refuses_the_network_kernel_state_and_a_second_process():
    """What would reach kernel state no namespace isolates, hold kernel memory no limit of
    the test's process counts, or make a second process is refused; threads, Python's
    temporary files, pipes and flock still work."""
    run = subprocess.run(
        [sys.executable, "-c", SECCOMP_PROBE.format(repo=str(REPO))],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout) == {
        "inet": "EPERM", "inet6": "EPERM", "netlink": "EPERM", "unix": "EPERM",
        "socketpair": "EPERM", "keyctl": "EPERM", "ptrace": "EPERM", "unshare": "EPERM",
        "bpf": "EPERM", "shmget": "EPERM", "mq_open": "EPERM", "fsopen": "EPERM",
        "memfd_create": "EPERM", "inotify_init1": "EPERM", "fanotify_init": "EPERM",
        "io_setup": "EPERM", "epoll": "EPERM", "clone_newuser": "EPERM", "clone_newns": "EPERM",
        "fork": "EPERM", "vfork": "EPERM", "clone3": "ENOSYS", "thread": "made",
        "O_TMPFILE": "ENOTSUP", "TemporaryFile": "made", "pipe bigger": "EPERM",
        "record lock": "EPERM", "flock": "made",
    }  # fmt: skip

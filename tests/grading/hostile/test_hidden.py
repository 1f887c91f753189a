"""Hidden inputs and outcomes never reach a visible test's output (5)."""

from __future__ import annotations

import os
import platform
import subprocess

import pytest

from hostile.deployed import (
    everything_visible,
    grade_as_deployed,
    scores,
    shown,
    submission_with,
    submission_wrapping,
    way,
)

pytestmark = pytest.mark.slow


# ---- 5: hidden inputs never reach a visible test's output ----------------------------------


def test_5_a_hidden_test_cannot_leave_its_inputs_for_a_visible_one(release, autograder, tmp_path):
    """The hidden ray-sphere tests (2.4, 2.5) hide their inputs everywhere they can write; the
    visible plane-side test (2.6) prints whatever it finds (it runs before them, as every
    visible test does: test_10_visible_tests_run_before_hidden_ones; the stashes would be gone
    in any order)."""
    stash = ["/tmp/stash", "/dev/shm/stash", "/var/tmp/stash", "/work/stash"]
    code = (
        "def hit_sphere(origins, directions, center, radius):\n    import os\n"
        f"    for path in {stash!r} + [os.path.expanduser('~/stash')]:\n"
        "        try:\n"
        "            open(path, 'w').write('HIDDEN-INPUTS ' + repr(center.tolist()))\n"
        "        except OSError:\n            pass\n"
        "    return _hit_sphere(origins, directions, center, radius)\n"
    )
    peek = (
        "def plane_side(p, a, n):\n    import os\n"
        f"    for path in {stash!r} + [os.path.expanduser('~/stash')]:\n"
        "        try:\n            print(open(path).read())\n"
        "        except OSError:\n            pass\n"
        "    print('uid', os.getuid())\n"
        "    return _plane_side(p, a, n)\n"
    )
    submission = submission_wrapping(
        tmp_path, {"spheres.py": ("hit_sphere", code), "planes.py": ("plane_side", peek)}
    )
    results, run = grade_as_deployed(autograder, submission, ["2.4", "2.5", "2.6"], tmp_path)
    assert list(scores(results)) == list(shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}))
    assert scores(results) == shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}), results
    visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
    assert "uid" in visible  # what it printed does show (a visible test)
    assert "HIDDEN-INPUTS" not in everything_visible(results)


def test_5_kernel_keyrings_carry_nothing_from_a_hidden_test(release, autograder, tmp_path):
    """A uid's keyring outlives its processes; the sandbox refuses the keyring system calls
    (seccomp), so a hidden test cannot leave its inputs there for a visible one."""
    from raykit_grading.sandbox.isolation import SECCOMP_ARCHES

    calls = SECCOMP_ARCHES[platform.machine()][1]
    keep = (
        "def hit_sphere(origins, directions, center, radius):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    data = b'HIDDEN-INPUTS ' + repr(center.tolist()).encode()\n"
        f"    libc.syscall({calls['add_key']}, b'user', b'stash', data, len(data), -4)\n"
        f"    libc.syscall({calls['add_key']}, b'user', b'stash', data, len(data), -3)\n"
        "    return _hit_sphere(origins, directions, center, radius)\n"
    )
    fetch = (
        "def plane_side(p, a, n):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    for ring in (-4, -3):\n"
        f"        key = libc.syscall({calls['request_key']}, b'user', b'stash', None, ring)\n"
        "        buffer = ctypes.create_string_buffer(4096)\n"
        f"        got = libc.syscall({calls['keyctl']}, 11, key, buffer, 4096)\n"
        "        print('keyring', ring, key, got, ctypes.get_errno(), buffer.value[:200])\n"
        "    return _plane_side(p, a, n)\n"
    )
    submission = submission_wrapping(
        tmp_path, {"spheres.py": ("hit_sphere", keep), "planes.py": ("plane_side", fetch)}
    )
    results, run = grade_as_deployed(autograder, submission, ["2.4", "2.5", "2.6"], tmp_path)
    assert scores(results) == shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}), results
    visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
    assert "keyring -4 -1 -1 1" in visible  # refused: EPERM
    assert "HIDDEN-INPUTS" not in everything_visible(results)


def test_5_system_v_ipc_carries_nothing_from_a_hidden_test(release, autograder, tmp_path):
    """A System V shared memory segment (like a message queue or a semaphore set) outlives
    its processes, and without an ipc namespace of its own (the chroot kind) every later
    test's uid could open one made mode 666; the sandbox refuses the System V and POSIX
    message queue calls (seccomp), so a hidden test cannot leave its inputs there."""
    shmget, msgget = {"x86_64": (29, 68), "aarch64": (194, 186)}[platform.machine()]
    key = 0x7A170000 + os.getpid() % 0x10000
    keep = (
        "def hit_sphere(origins, directions, center, radius):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    libc.syscall.restype = ctypes.c_long\n    libc.shmat.restype = ctypes.c_void_p\n"
        "    data = b'HIDDEN-INPUTS ' + repr(center.tolist()).encode() + b'\\0'\n"
        f"    shm = libc.syscall({shmget}, {key}, 4096, 0o1666)\n"
        "    if shm >= 0:\n"
        "        address = libc.shmat(int(shm), None, 0)\n"
        "        if address not in (None, 2**64 - 1):\n"
        "            ctypes.memmove(address, data, len(data))\n"
        f"    libc.syscall({msgget}, {key}, 0o1666)\n"
        "    return _hit_sphere(origins, directions, center, radius)\n"
    )
    fetch = (
        "def plane_side(p, a, n):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    libc.syscall.restype = ctypes.c_long\n    libc.shmat.restype = ctypes.c_void_p\n"
        f"    shm = libc.syscall({shmget}, {key}, 0, 0)\n"
        "    print('shm', shm, ctypes.get_errno())\n"
        "    if shm >= 0:\n"
        "        address = libc.shmat(int(shm), None, 0o10000)\n"
        "        if address not in (None, 2**64 - 1):\n"
        "            print(ctypes.string_at(address)[:200])\n"
        f"    print('msg', libc.syscall({msgget}, {key}, 0), ctypes.get_errno())\n"
        "    return _plane_side(p, a, n)\n"
    )
    submission = submission_wrapping(
        tmp_path, {"spheres.py": ("hit_sphere", keep), "planes.py": ("plane_side", fetch)}
    )
    try:
        results, run = grade_as_deployed(autograder, submission, ["2.4", "2.5", "2.6"], tmp_path)
    finally:  # were the defence gone, what it made would outlive the test on this machine
        for kind in ("-M", "-Q"):
            subprocess.run(["ipcrm", kind, hex(key)], capture_output=True)
    assert scores(results) == shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}), results
    visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
    assert "shm -1 1" in visible and "msg -1 1" in visible  # refused: EPERM
    assert "HIDDEN-INPUTS" not in everything_visible(results)


def test_5_a_hidden_tests_error_message_is_not_shown(release, autograder, tmp_path):
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    raise ValueError('INPUTS ' + repr(origins.tolist()))\n"
    )
    submission = submission_with(release, tmp_path, {"planes.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.2", "2.1"], tmp_path)
    assert scores(results) == shown(autograder, {"2.2": 0, "2.1": 0})
    visible, hidden = results["tests"]  # in the catalogue's order (PrairieLearn: hidden last)
    if way(autograder) == "prairielearn":  # one line, nothing of the hidden test's own
        assert hidden["output"].startswith("hidden tests: 0 of 1 points")
    else:
        assert hidden["output"].startswith("your code stopped with an error (a hidden test")
    assert "INPUTS" not in hidden["output"] and "INPUTS" in visible["output"]

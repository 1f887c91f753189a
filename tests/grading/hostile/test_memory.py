"""Memory beyond the limits: no namespace of its own, nothing the kernel holds outside the
limit, an init that outlives the test, a tmp to fill (9); and every budget holds, with
nothing shown at once that tells of a hidden test (11)."""

from __future__ import annotations

import re

import pytest
from budget_attacks import budget_attacker

from hostile.deployed import (
    POINTS,
    grade_as_deployed,
    leftovers_no_grader_holds,
    scores,
    shown,
    submission_wrapping,
    way,
)
from mistaken_submissions import make_submission

pytestmark = pytest.mark.slow


def test_9_no_namespace_of_its_own_so_no_memory_beyond_its_limits(release, autograder, tmp_path):
    """clone(CLONE_NEWUSER | CLONE_NEWNS) would make the child root of a user namespace of
    its own (bubblewrap as root leaves that to the kernel), where the new mount API mounts a
    tmpfs that neither the 64 MB /tmp nor the address-space limit bounds. The seccomp filter
    refuses a clone with any CLONE_NEW* flag and the new mount API; the code answers right
    only if it stored nothing."""
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    import os, ctypes, platform\n"
        "    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    libc.syscall.restype = ctypes.c_long\n"
        "    clone = {'x86_64': 56, 'aarch64': 220}[platform.machine()]\n"
        "    libc.prctl(4, 1, 0, 0, 0)  # PR_SET_DUMPABLE: its own /proc files, for uid_map\n"
        "    uid, gid = os.getuid(), os.getgid()\n"
        "    said_r, said_w = os.pipe()\n    go_r, go_w = os.pipe()\n"
        "    pid = libc.syscall(clone, 0x10000000 | 0x00020000 | 17, 0, 0, 0, 0)\n"
        "    if pid == 0:\n"
        "        os.read(go_r, 1)\n        stored = 0\n"
        "        fs = libc.syscall(430, b'tmpfs', 0)  # fsopen\n"
        "        if fs >= 0:\n"
        "            libc.syscall(431, fs, 6, None, None, 0)  # FSCONFIG_CMD_CREATE\n"
        "            mnt = libc.syscall(432, fs, 0, 0)  # fsmount\n"
        "            try:\n"
        "                out = os.open('big', os.O_CREAT | os.O_WRONLY, 0o600, dir_fd=mnt)\n"
        "                for _ in range(200):\n"
        "                    os.write(out, b'x' * 2**20)\n                    stored += 1\n"
        "            except OSError:\n                pass\n"
        "        os.write(said_w, str(stored).encode())\n        os._exit(0)\n"
        "    print('clone', pid, ctypes.get_errno())\n"
        "    stored = 0\n"
        "    if pid > 0:\n"
        "        for name, text in (('setgroups', 'deny'), ('uid_map', f'0 {uid} 1'),\n"
        "                           ('gid_map', f'0 {gid} 1')):\n"
        "            try:\n                open(f'/proc/{pid}/{name}', 'w').write(text)\n"
        "            except OSError:\n                pass\n"
        "        os.write(go_w, b'g')\n        os.waitpid(pid, 0)\n"
        "        stored = int(os.read(said_r, 20) or 0)\n"
        "    print('stored', stored, 'MB')\n"
        "    return _hit_plane(origins, directions, a, n) if not stored else origins[:, 0]\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "clone -1 " in results["tests"][0]["output"]  # refused: EPERM, or ENOSPC as a user
    assert "stored 0 MB" in results["tests"][0]["output"]


def test_9_no_gigabyte_held_by_the_kernel_outside_the_memory_limit(release, autograder, tmp_path):
    """The address-space limit does not count what the kernel holds for a process: memfd
    files (never mapped) and socket buffers. It tries to hold 1 GB in each: memfd_create and
    every socket are refused (seccomp). The code answers right only if it never held 1 GB."""
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    import os, socket\n"
        "    GB, chunk, held, keep = 2**30, b'x' * 2**20, {'memfd': 0, 'sockets': 0}, []\n"
        "    try:\n"
        "        while held['memfd'] < GB:\n"
        "            keep.append(os.memfd_create('hog'))\n"
        "            for _ in range(60):\n"
        "                held['memfd'] += os.write(keep[-1], chunk)\n"
        "    except OSError as e:\n        print('memfd', e.errno)\n"
        "    for fd in keep:\n        os.close(fd)\n"
        "    try:\n"
        "        while held['sockets'] < GB:\n"
        "            pair = socket.socketpair()\n            keep.append(pair)\n"
        "            for end in pair:\n"
        "                end.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 2**23)\n"
        "                end.setblocking(False)\n"
        "                try:\n"
        "                    while held['sockets'] < GB:\n"
        "                        held['sockets'] += end.send(chunk)\n"
        "                except BlockingIOError:\n                    pass\n"
        "    except OSError as e:\n        print('sockets', e.errno)\n"
        "    print('held MB', {k: v >> 20 for k, v in held.items()})\n"
        "    big = max(held.values()) >= GB\n"
        "    return origins[:, 0] if big else _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "memfd 1" in results["tests"][0]["output"]  # refused: EPERM
    assert "sockets 1" in results["tests"][0]["output"]  # refused: EPERM


def test_9_the_sandbox_init_cannot_be_rewritten_to_outlive_the_test(release, autograder, tmp_path):
    """As a normal user, bubblewrap's init (pid 1 in the sandbox) runs as the child's own uid:
    with a /proc the child could write that process's memory through /proc/1/mem (run code
    there that leaves the process group and drops --die-with-parent, and so outlive the
    test). There is no /proc in any sandbox; the code answers right only if it could not
    write another process's memory."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os\n    wrote = 0\n"
        "    try:\n"
        "        maps = open('/proc/1/maps').read().splitlines()\n"
        "        start = int(next(m for m in maps if 'r-xp' in m).split('-')[0], 16)\n"
        "        memory = os.open('/proc/1/mem', os.O_RDWR)\n"
        "        same = os.pread(memory, 4, start)\n"
        "        wrote = os.pwrite(memory, same, start)  # its own bytes: the test harms nothing\n"
        "    except (OSError, StopIteration) as e:\n"
        "        print('refused', type(e).__name__)\n"
        "    print('wrote', wrote)\n"
        "    return origins[:, 0] if wrote else _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "wrote 0" in results["tests"][0]["output"]


def test_9_no_memory_is_there_to_fill_but_a_small_tmp(release, autograder, tmp_path):
    """Writing 100 MB anywhere fails: the tree is read-only but /tmp, which is 64 MB. The code
    answers right only if every big write failed."""
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    stored = []\n"
        "    for path in ('/big', '/dev/shm/big', '/dev/big', '/tmp/big', '/work/big'):\n"
        "        try:\n"
        "            with open(path, 'wb') as out:\n"
        "                for _ in range(100):\n"
        "                    out.write(b'x' * 2**20)\n"
        "            stored.append(path)\n"
        "        except OSError:\n            pass\n"
        "    print('stored', stored)\n"
        "    return _hit_plane(origins, directions, a, n) if not stored else origins[:, 0]\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "stored []" in results["tests"][0]["output"]


# ---- 11: every budget holds, and nothing shown at once tells of a hidden test ----------------

# tests/support/budget_attacks.py, all in one submission: each attack in a function of its own
BUDGETED = ["2.1", "2.3", "2.4", "2.5", "2.6", "2.7", "4.1", "4.2"]
BUDGETED_SCORES = {"2.1": 0, "2.3": 2, "2.4": 0, "2.5": 0, "2.6": 1, "2.7": 1, "4.1": 0, "4.2": 0}
# the page tables' 480 MB are within a test's memory where no container (root, user) or a
# 2 GB one (PrairieLearn's) leaves it more, past it at Gradescope's 768 MB (docker, container)
PAGE_TABLES_WITHIN = ("root", "user", "prairielearn")
BUDGETED_SAY = {  # what each visible test's output says
    "2.1": ["your code used more disk than allowed", "with no name"],
    "2.6": ["socketpair 1", "fork 1", "F_SETPIPE_SZ 1", "held 0 MB"],
    "2.7": ["fork 1", "children held 0 MB"],
    "4.1": ["your code used more memory than allowed", "page tables"],
    "4.2": ["returned something that is not plain arrays", "more than 16 arrays"],
}
PEAK = re.compile(r"raykit_grading: the grader's peak memory: (\d+) MB of the (\d+) MB it keeps")
OOM = re.compile(r"the container's OOM killer fired (\d+) times")


def test_11_every_budget_holds_and_hidden_outcomes_stay_hidden(autograder, tmp_path):
    """Files with no name, kernel buffers in sockets and pipes, memory across processes, page
    tables, an archive of 100,000 empty members, and hidden tests that fail: every test past a
    budget is stopped and told which, what must be refused is, and the summary shown at once
    is the honest submission's. The grader stays within its own memory, the container's OOM
    killer never fires, nothing is left, and the honest submission graded next scores in full.
    (That execution_time counts the visible tests only is test_grading's, on a clock of its
    own.)"""
    attacker = budget_attacker(tmp_path / "attack" / "submission")
    results, run = grade_as_deployed(autograder, attacker, BUDGETED, tmp_path / "a")
    print(way(autograder), scores(results), results["output"])
    print({t["number"]: t["output"][-600:] for t in results["tests"]}, run.stderr[-1500:])
    assert run.returncode == 0, run.stderr[-2000:]
    within = way(autograder) in PAGE_TABLES_WITHIN
    assert scores(results) == shown(autograder, {**BUDGETED_SCORES, "4.1": int(within)}), results
    said = {t["number"]: t["output"] for t in results["tests"]}
    for key, words in BUDGETED_SAY.items():
        words = ["MAPPINGS 20000"] if key == "4.1" and within else words
        assert all(w in said[key] for w in words), (key, said[key])
    assert leftovers_no_grader_holds() == []
    honest = make_submission(tmp_path / "honest" / "submission")
    fair, fair_run = grade_as_deployed(autograder, honest, BUDGETED, tmp_path / "h")
    assert fair_run.returncode == 0, fair_run.stderr[-2000:]
    assert scores(fair) == shown(autograder, {k: POINTS[k] for k in BUDGETED}), fair
    summary = [  # shown at once: the visible tests' sums, and of the hidden ones no outcome
        "Stage 2 rays, planes and spheres: 4 of 6 points, 3 of 4 visible tests pass",
        f"Stage 4 shading, shadows and mirrors: {int(within)} of 2 points, {int(within)} of 2 "
        "visible tests pass",
        "Hidden tests: 2, 3 points (how they went is not shown here)",
    ]
    assert results["output"].splitlines()[1:] == summary, results["output"]
    assert fair["output"].splitlines()[-1] == summary[-1]
    for graded in (run, fair_run):
        peak = PEAK.search(graded.stderr)
        assert peak and int(peak.group(1)) <= int(peak.group(2)), graded.stderr[-1500:]
        if way(autograder) in ("docker", "container", "prairielearn"):
            assert OOM.search(graded.stderr).group(1) == "0", graded.stderr[-1500:]

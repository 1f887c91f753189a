"""Memory beyond the limits: no namespace of its own, nothing the kernel holds outside the
limit, an init that outlives the test, a tmp to fill (9); and every budget holds, with
nothing shown at once that tells of a hidden test (11), in a batch too, where honest students
between attackers score in full."""

from __future__ import annotations

import csv
import html
import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from budget_attacks import budget_attacker

from conftest import REPO
from hostile.deployed import (
    AS_ROOT,
    NOBODY,
    POINTS,
    SEED,
    grade_as_deployed,
    leftovers_no_grader_holds,
    scores,
    shown,
    submission_wrapping,
    way,
)
from hostile.test_leftovers import DEEP_TREE, WRITES_TOO_MUCH
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS

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
    fair, fair_run = grade_as_deployed(autograder, honest, BUDGETED, tmp_path / "h", wall=None)
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


# batch runs on an instructor's machine, as root or as a normal user (bubblewrap's sandbox);
# in a container only run_autograder and PrairieLearn's entrypoint grade, one submission each
BATCH_WAYS = ("root", "user")


@pytest.mark.parametrize("graded_as", BATCH_WAYS)
def test_11_a_batch_grades_honest_students_between_attackers_in_full(graded_as, tmp_path):
    """One batch on one machine grades ada, then mallory (issue 40's disk: a tree too deep to
    name, 200 files of 50 MB), then trudy (every attack of tests/support/budget_attacks.py),
    then zoe: ada and zoe score in full, test for test; mallory and trudy exactly what
    test_10's and test_11's attacks score, each of their pages (linked from the class report)
    naming the budget that stopped them; every student's grader stays within its own memory
    (its log, ``logs/<student>.log``), the OOM killer never fires where its cgroup says, and
    nothing is left."""
    students = tmp_path / "submissions"
    make_submission(students / "ada")
    mallory = submission_wrapping(
        tmp_path / "m",
        {
            "planes.py": ("hit_plane", DEEP_TREE),
            "spheres.py": (
                "hit_sphere",
                WRITES_TOO_MUCH.replace("hit_plane", "hit_sphere").replace(
                    "origins, directions, a, n", "origins, directions, center, radius"
                ),
            ),
        },
    )
    shutil.copytree(mallory, students / "mallory")
    budget_attacker(students / "trudy")
    make_submission(students / "zoe")
    out, run = _batch_as(graded_as, students, tmp_path / "graded")
    assert run.returncode == 0, run.stderr[-2000:]
    rows = {row["student"]: row for row in csv.DictReader((out / "scores.csv").open())}
    full = {k: POINTS[k] for k in BUDGETED}
    within = int(graded_as in PAGE_TABLES_WITHIN)
    assert {k: (r["status"], {t: float(r[t]) for t in BUDGETED}) for k, r in rows.items()} == {
        "ada": ("graded", full),
        "mallory": ("graded", {**full, "2.1": 0, "2.3": 0, "2.4": 0, "2.5": 0}),
        "trudy": ("graded", {**BUDGETED_SCORES, "4.1": within}),
        "zoe": ("graded", full),
    }, run.stderr[-2000:]
    report = (out / "report.html").read_text()
    pages = {name: html.unescape((out / "feedback" / name / "index.html").read_text())
             for name in rows if f"href='feedback/{name}/index.html'" in report}  # fmt: skip
    assert sorted(pages) == sorted(rows), report
    stopped = {("mallory", "2.1"): "used more disk than allowed",
               ("mallory", "2.3"): "used more disk than allowed",
               ("trudy", "2.1"): BUDGETED_SAY["2.1"][0], ("trudy", "4.2"): BUDGETED_SAY["4.2"][0],
               **({} if within else {("trudy", "4.1"): BUDGETED_SAY["4.1"][0]})}  # fmt: skip
    for (name, key), budget in stopped.items():  # on the page the report links
        told = re.sub(r"<[^>]+>", " ", _failing_on(pages[name], key))
        assert budget in told, f"{name}'s {key} was not stopped for {budget!r}: {told!r}"
    trudy = json.loads((out / "feedback/trudy/results.json").read_text())
    said = {t["number"]: t["output"] for t in trudy["tests"]}
    for key, words in {**BUDGETED_SAY, **({"4.1": ["MAPPINGS 20000"]} if within else {})}.items():
        assert all(w in said[key] for w in words), (
            f"trudy's {key} does not say {words}: {said[key]!r}"
        )
    for name in rows:
        log = (out / "logs" / f"{name}.log").read_text()
        peak = PEAK.search(log)
        assert peak and int(peak.group(1)) <= int(peak.group(2)), (name, log[-1500:])
        killed = OOM.search(log)  # a container's cgroup says; an instructor's machine may not
        assert killed is None or killed.group(1) == "0", (name, log[-1500:])
    assert leftovers_no_grader_holds() == []


def _failing_on(page: str, key: str) -> str:
    """What a student's feedback page says of test ``key`` where it lists it as failing ("" if
    it does not)."""
    name = next(t.name for t in TESTS if t.key == key)
    found = re.search(f"FAIL: {re.escape(name)}:(.*?)</section>", page, re.S)
    return found.group(1) if found else ""


def _batch_as(
    graded_as: str, students: Path, out: Path
) -> tuple[Path, subprocess.CompletedProcess]:
    """``python -m raykit_grading batch`` of ``students`` with the budgeted tests, one student
    at a time, each test with its own wall time: as root (``root``), or as a normal user
    (``user``: as root, uid 65534 through ``setpriv`` with a Python of raykit's dependencies,
    in a folder of its own, its TMPDIR, which must hold nothing of the graders afterwards);
    returns OUT and the run."""

    def batch(python: str, students: Path, out: Path) -> list[str]:
        # a test's own wall time, as an instructor's batch has it: every attack here is
        # stopped by its budget or let be long before it while its defences hold (and one
        # that is not shows as its time running out), and the page tables' 20,000 mappings
        # (4.1, within its budget here) must not be stopped by the time a loaded machine takes
        return [python, "-m", "raykit_grading", "batch", str(students), "-o", str(out),
                "--only", *BUDGETED, "--jobs", "1", "--seed", str(SEED)]  # fmt: skip

    if graded_as == "root" and not AS_ROOT:
        pytest.skip("the root way runs batch as root")
    if graded_as == "root" or not AS_ROOT:  # as the suite's user
        run = subprocess.run(batch(sys.executable, students, out), capture_output=True,
                             text=True, cwd=out.parent, timeout=900)  # fmt: skip
        return out, run
    from grader_python import instructor_python

    python, why = instructor_python()
    if python is None or shutil.which("setpriv") is None:
        pytest.skip(why or "as root, the user way needs setpriv to become uid 65534")
    home = Path(tempfile.mkdtemp(prefix="raykit-user-", dir="/tmp"))
    try:
        shutil.copytree(students, home / "submissions")
        (home / "home").mkdir()  # matplotlib's cache and configuration
        subprocess.run(["chown", "-R", f"{NOBODY}:{NOBODY}", str(home)], check=True)
        run = subprocess.run(
            ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups",
             *batch(python, home / "submissions", home / "out")],
            capture_output=True, text=True, timeout=900, cwd=home,
            env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(REPO), "TMPDIR": str(home),
                 "HOME": str(home / "home")},
        )  # fmt: skip
        left = sorted(
            p.name for p in home.iterdir() if p.name not in ("submissions", "out", "home")
        )
        assert left == [], f"the graders left {left} in their TMPDIR"
        shutil.copytree(home / "out", out)
    finally:
        shutil.rmtree(home, ignore_errors=True)
    return out, run

"""What one test leaves reaches no other test (10; no later student: test_memory.py's batch),
and nothing is left behind by any way of grading."""

from __future__ import annotations

import json
import os
import re
import shutil
import socket
import subprocess
from pathlib import Path

import pytest

from hostile.deployed import (
    CONTAINERS,
    everything_visible,
    grade_as_deployed,
    leftovers_no_grader_holds,
    sandbox_processes_no_grader_holds,
    scores,
    submission_wrapping,
    way,
)
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS

pytestmark = pytest.mark.slow


# ---- 10: what one test leaves reaches no other test, and no later student -----------------

# the attacks of this section, each written into the solution's hit_plane (test 2.1), which
# then answers right: a test that keeps to its disk budget keeps its score
DEEP_TREE = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    here = os.open(os.environ['HOME'], os.O_RDONLY)\n"
    "    for _ in range(200_000):\n"
    "        os.mkdir('d', dir_fd=here)\n"
    "        deeper = os.open('d', os.O_RDONLY, dir_fd=here)\n"
    "        os.close(here)\n        here = deeper\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
RESERVED = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    fd = os.open(os.path.join(os.environ['HOME'], 'big'), os.O_CREAT | os.O_WRONLY)\n"
    "    try:\n        os.posix_fallocate(fd, 0, 960 * 2**20)\n"
    "    except OSError as e:\n        print('FALLOCATE', e.errno)\n"
    "    os.ftruncate(fd, 60 * 2**20)  # sparse: no block held\n"
    "    print('HELD', os.fstat(fd).st_blocks * 512)\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
WRITES_TOO_MUCH = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    block = b'x' * 2**20\n"
    "    for i in range(200):\n"
    "        with open(os.path.join(os.environ['HOME'], f'f{i}'), 'wb') as f:\n"
    "            for _ in range(50):\n                f.write(block)\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
CLOSED_LEFTOVERS = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    home = os.environ['HOME']\n"
    "    os.makedirs(os.path.join(home, 'a/b/c'))\n"
    "    os.mkfifo(os.path.join(home, 'a/b/c/pipe'))\n"
    "    open(os.path.join(home, 'a/b/file'), 'w').write('x')\n"
    "    for folder in ('a/b/c', 'a/b', 'a'):\n"
    "        os.chmod(os.path.join(home, folder), 0)\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
DISK_ATTACKS = {
    "a tree too deep to name": (DEEP_TREE, 0, "used more disk than allowed"),
    "200 files of 50 MB": (WRITES_TOO_MUCH, 0, "used more disk than allowed"),
    "960 MB reserved, 60 MB sparse": (RESERVED, 2, "FALLOCATE 1\nHELD 0"),
    "folders closed to their owner, a FIFO": (CLOSED_LEFTOVERS, 2, "the grader removed them"),
}


@pytest.mark.parametrize("name", sorted(DISK_ATTACKS))
def test_10_disk_attacks_cost_their_own_test_and_leave_nothing(name, autograder, tmp_path):
    """Each attack in 2.1, beside an honest 2.3: the attack's test scores what its budget
    allows (a test past its budget is stopped and scores 0, saying so; one within it keeps
    its score, told what the grader had to force), 2.3 is graded in full, nothing is left on
    disk, and the solution graded right after on the same machine scores in full."""
    code, points, says = DISK_ATTACKS[name]
    submission = submission_wrapping(tmp_path / "attack", {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "2.3"], tmp_path / "a")
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": points, "2.3": 2}, results
    assert says in results["tests"][0]["output"], results["tests"][0]["output"]
    assert "autograder failed" not in everything_visible(results)
    assert leftovers_no_grader_holds() == []
    honest = make_submission(tmp_path / "honest" / "submission")
    results, run = grade_as_deployed(autograder, honest, ["2.1", "2.3"], tmp_path / "h", wall=None)
    assert run.returncode == 0 and scores(results) == {"2.1": 2, "2.3": 2}, results


SPY = (
    "def plane_side(p, a, n):\n    import os, json\n"
    "    home = os.environ['HOME']\n    seen = {{}}\n"
    "    looks = [('parent', '..'), ('here', '.'), ('tmp', home), ('tmp parent', home + '/..')]\n"
    "    for what, path in looks:\n"
    "        try:\n"
    "            got = os.stat(path)\n"
    "            seen[what] = [got.st_nlink, got.st_size]\n"
    "        except OSError as e:\n            seen[what] = e.strerror\n"
    "    seen['tmp entries'] = sorted(os.listdir(home))\n"
    "    try:\n        seen['free inodes'] = os.statvfs(home).f_ffree\n"
    "    except OSError as e:\n        seen['free inodes'] = e.strerror\n"
    "    print('SPY', json.dumps(seen, sort_keys=True))\n"
    "    return _plane_side(p, a, n)\n"
)
LEAVE = (
    "def hit_sphere(origins, directions, center, radius):\n    import os\n"
    "    home = os.environ['HOME']\n"
    "    count = int(abs(center[0]) * 100) % 500 + 1  # the hidden input, as a count\n"
    "    for i in range(count):\n        os.mkdir(os.path.join(home, f'x{{i}}'))\n"
    "    return _hit_sphere(origins, directions, center, radius)\n"
)


def test_10_visible_tests_run_before_hidden_ones():
    from raykit_grading.assignment.catalog import VISIBLE
    from raykit_grading.grading.grade import _visible_first

    order = [t.visibility == VISIBLE for t in _visible_first(TESTS)]
    assert order == sorted(order, reverse=True) and order.count(True) == sum(
        t.visibility == VISIBLE for t in TESTS
    )


def test_10_a_test_sees_nothing_of_the_tests_before_it(release, autograder, tmp_path):
    """Hidden 2.4 and 2.5 leave folders in their tmp/ counted from their inputs; visible
    2.6 (graded with them) and 2.1's plane side look at everything they can stat: their
    folder's parent, their tmp/ and its parent, the free inodes. What each visible test sees is
    the same, whatever ran before it: the folder's parent and tmp/ are the same fixed ones,
    tmp/ is empty, and the file system's counts are refused. (Their times are not compared: a
    folder is as old as the grading or its container, which says nothing of an earlier test,
    and comparing their age with a few seconds failed on a loaded machine.)"""
    submission = submission_wrapping(
        tmp_path,
        {"spheres.py": ("hit_sphere", LEAVE.format()), "planes.py": ("plane_side", SPY.format())},
    )
    seen = []
    for only in (["2.6"], ["2.4", "2.5", "2.6"], ["2.3", "2.4", "2.6"]):
        results, run = grade_as_deployed(autograder, submission, only, tmp_path / "-".join(only))
        assert run.returncode == 0, run.stderr[-2000:]
        visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
        seen.append(re.search(r"SPY (.*)", visible).group(1))
    assert seen[0] == seen[1] == seen[2], seen
    facts = json.loads(seen[0])
    assert facts["tmp entries"] == [] and facts["free inodes"] == "Operation not permitted"


def test_removal_copes_with_any_tree_a_child_can_leave(tmp_path):
    """Folders nested deeper than a path can name, closed to their owner, FIFOs, sockets and
    links: removed by a walk that never recurses; as a normal user too, where the owner must
    open what it closed."""
    from raykit_grading.sandbox.leftovers import remove_tree

    def plant(top: Path) -> None:
        here = os.open(top, os.O_RDONLY)
        for _ in range(1500):  # 1500 x len("nested/") passes PATH_MAX
            os.mkdir("nested", dir_fd=here)
            deeper = os.open("nested", os.O_RDONLY, dir_fd=here)
            os.close(here)
            here = deeper
        os.mkfifo("pipe", dir_fd=here)
        os.symlink("/etc/passwd", "link", dir_fd=here)
        os.close(here)
        (top / "closed" / "inner").mkdir(parents=True)
        (top / "closed" / "inner" / "file").write_text("x")
        bound = socket.socket(socket.AF_UNIX)
        bound.bind(str(top / "closed" / "socket"))
        bound.close()
        os.chmod(top / "closed" / "inner", 0)
        os.chmod(top / "closed", 0o500)

    tree = tmp_path / "left"
    tree.mkdir()
    plant(tree)
    with pytest.raises((RecursionError, OSError)):
        shutil.rmtree(tree)  # what the grader used to call: raises part way, or never ends
    removal = remove_tree(tree, tmp_path / "quarantine")
    assert removal.problem == "" and not tree.exists() and removal.left_in is None
    assert removal.forced == {
        "special files (FIFOs, sockets or devices)",
        "folders closed to their owner",
    }
    assert os.listdir(tmp_path) == []


def test_removal_sets_aside_what_it_cannot_finish_in_time(tmp_path):
    from raykit_grading.sandbox.leftovers import remove_tree

    tree = tmp_path / "left"
    (tree / "a" / "b").mkdir(parents=True)
    removal = remove_tree(tree, tmp_path / "quarantine", seconds=-1)
    assert not tree.exists() and removal.left_in.parent == tmp_path / "quarantine"
    assert "took too long" in removal.problem and (removal.left_in / "a").is_dir()


@pytest.mark.skipif(os.geteuid() != 0, reason="only root may start a process of a sandbox uid")
def test_a_process_of_a_sandbox_uid_no_grader_holds_is_found_and_one_held_is_not():
    """What test_nothing_is_left_behind counts on: a leftover is found at every look, and a
    uid a grader holds is not a leftover. (The leftover lives a fraction of one look's pause,
    so a check on another worker, which must see it at each of its looks, never counts it.)"""
    import fcntl

    from raykit_grading.sandbox.isolation import SANDBOX_UIDS, UID_LOCKS, UidPool, kill_uid

    UidPool()  # makes UID_LOCKS
    uid = SANDBOX_UIDS[-1]
    child = subprocess.Popen(["sleep", "60"], user=uid, group=uid)
    try:
        assert str(child.pid) in sandbox_processes_no_grader_holds(looks=2, pause=0.05)
        lock = os.open(UID_LOCKS / str(uid), os.O_RDWR | os.O_CREAT, 0o600)
        try:
            fcntl.flock(lock, fcntl.LOCK_EX)
            assert str(child.pid) not in sandbox_processes_no_grader_holds(looks=1)
        finally:
            os.close(lock)
    finally:
        kill_uid(uid)
        child.wait()


def test_nothing_is_left_behind(autograder):
    """No process of a sandbox uid, no grader workspace, nothing in a chroot tree's test
    folder and nothing in a quarantine that no running grader holds (this runs after the
    tests above, for each way)."""
    if way(autograder) in ("container", "prairielearn"):  # every grading's container
        for name in CONTAINERS:  # removed (by its name: others may grade on the same daemon)
            inspected = subprocess.run(
                ["docker", "container", "inspect", name], capture_output=True
            )
            assert inspected.returncode != 0, f"container {name} left"
    assert leftovers_no_grader_holds() == []
    assert sandbox_processes_no_grader_holds() == []

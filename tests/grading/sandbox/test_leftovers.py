"""What a test's code leaves on disk (raykit_grading.sandbox.leftovers), on trees made here: its
budget counted in blocks held, entries and depth, links never followed; every kind of entry
removed, however deep and however closed, and nothing a link points to; what cannot be removed
in time moved to the quarantine and said, never raised. (The same against hostile submissions,
graded end to end: hostile/test_leftovers.py.)"""

from __future__ import annotations

import os
import socket
import stat
from pathlib import Path

from raykit_grading.sandbox.leftovers import DiskBudget, Removal, measure, remove_tree

MB = 2**20


def _outside(tmp_path: Path) -> tuple[Path, Path]:
    """A file and a folder of 5 MB each outside the test's tree, for its links to point to."""
    elsewhere = tmp_path / "elsewhere"
    (elsewhere / "folder").mkdir(parents=True)
    (elsewhere / "folder/data").write_bytes(os.urandom(5 * MB))
    (elsewhere / "file").write_bytes(os.urandom(5 * MB))
    return elsewhere / "file", elsewhere / "folder"


def _leftovers(folder: Path, outside: tuple[Path, Path]) -> Path:
    """A test's tmp/ as a hostile child leaves it: 2 MB held, 100 MB sparse, links out, a FIFO,
    a socket, nested folders, one closed to its owner (mode 000) and one it may not write."""
    folder.mkdir()
    (folder / "held").write_bytes(os.urandom(2 * MB))
    with open(folder / "sparse", "wb") as sparse:
        sparse.truncate(100 * MB)
    (folder / "to-file").symlink_to(outside[0])
    (folder / "to-folder").symlink_to(outside[1])
    os.mkfifo(folder / "fifo")
    with socket.socket(socket.AF_UNIX) as listening:
        listening.bind(str(folder / "sock"))
    (folder / "a/b/c").mkdir(parents=True)
    (folder / "a/b/c/deep").write_text("x")
    (folder / "closed").mkdir()
    (folder / "closed/inside").write_text("x")
    (folder / "read-only").mkdir()
    (folder / "read-only/inside").write_text("x")
    os.chmod(folder / "closed", 0)
    os.chmod(folder / "read-only", 0o500)
    return folder


def test_the_budget_counts_blocks_held_entries_and_depth_never_through_a_link(tmp_path):
    tmp = _leftovers(tmp_path / "tmp", _outside(tmp_path))
    os.chmod(tmp / "closed", 0o700)
    (tmp / "closed/inside").write_bytes(os.urandom(MB))  # counted, closed as it is
    os.chmod(tmp / "closed", 0)
    # 14 entries; a/b/c is 4 folders open; 3 MB held (and the folders' and links' blocks):
    # the sparse file's 100 MB and the 10 MB the links point to hold nothing of the budget's
    within = DiskBudget(bytes=4 * MB, entries=14, depth=4)
    assert within.describe() == "4 MB, 14 files and folders, folders 4 deep"
    assert measure(tmp, within) == ""
    assert measure(tmp, DiskBudget(bytes=2 * MB + MB // 2, entries=14, depth=4)) == (
        "more than 2 MB"  # only with what the closed folder holds
    )
    assert measure(tmp, within, already=2 * MB) == "more than 4 MB"
    assert measure(tmp, DiskBudget(bytes=4 * MB, entries=13, depth=4)) == (
        "more than 13 files and folders"
    )
    assert measure(tmp, DiskBudget(bytes=4 * MB, entries=14, depth=3)) == (
        "folders more than 3 deep"
    )
    assert measure(tmp_path / "never-made", within) == ""


def test_every_kind_of_entry_is_removed_and_nothing_a_link_points_to(tmp_path):
    outside = _outside(tmp_path)
    tmp = _leftovers(tmp_path / "tmp", outside)
    removal = remove_tree(tmp, tmp_path / "quarantine")
    assert removal == Removal(
        entries=14,  # 11 files, links, a FIFO and a socket, and 5 folders, in all
        forced={"special files (FIFOs, sockets or devices)", "folders closed to their owner"},
    )
    assert not os.path.lexists(tmp) and os.listdir(tmp_path) == ["elsewhere"]
    assert outside[0].stat().st_size == 5 * MB and (outside[1] / "data").stat().st_size == 5 * MB


def test_a_tree_deeper_than_a_path_can_name_is_removed(tmp_path):
    name = "d" * 200
    top = os.open(tmp_path, os.O_RDONLY | os.O_DIRECTORY)
    for _ in range(60):  # 12,000 characters: three times the longest path Linux opens
        os.mkdir(name, dir_fd=top)
        inner = os.open(name, os.O_RDONLY | os.O_DIRECTORY, dir_fd=top)
        os.close(top)
        top = inner
    os.close(top)
    removal = remove_tree(tmp_path / name)
    assert (removal.entries, removal.problem, os.listdir(tmp_path)) == (59, "", [])


def test_what_is_not_removed_in_time_goes_to_the_quarantine_and_is_said(tmp_path):
    tmp = _leftovers(tmp_path / "tmp", _outside(tmp_path))
    quarantine = tmp_path / "quarantine"
    removal = remove_tree(tmp, quarantine, seconds=-1)  # its time up before it starts
    assert removal.left_in is not None and removal.left_in.parent == quarantine
    assert removal.problem == (
        f"could not remove everything in {tmp} (it took too long): moved to {removal.left_in}"
    )
    assert not os.path.lexists(tmp) and stat.S_IMODE(quarantine.stat().st_mode) == 0o700
    assert (removal.left_in / "a/b/c/deep").is_file()  # what was left, there
    again = _leftovers(tmp_path / "tmp", _outside(tmp_path / "again"))
    kept = remove_tree(again, None, seconds=-1)  # nowhere to move it: where it is, said
    said, _, holding = kept.problem.partition(": left in ")
    assert kept.left_in is None
    assert said == f"could not remove everything in {again} (it took too long)"
    assert Path(holding).parent == tmp_path and Path(holding).name.startswith(".removing-")
    assert (Path(holding) / "a/b/c/deep").is_file()


def test_a_link_is_removed_itself_and_a_missing_path_is_nothing_to_do(tmp_path):
    target = tmp_path / "folder"
    (target / "inside").mkdir(parents=True)
    (tmp_path / "link").symlink_to(target)
    assert remove_tree(tmp_path / "link") == Removal(entries=1, forced=set())
    assert (target / "inside").is_dir() and not os.path.lexists(tmp_path / "link")
    assert remove_tree(tmp_path / "never-made") == Removal(forced=set())

"""The grader's own private temporary folder (raykit_grading.sandbox.workspace)."""

from __future__ import annotations

import fcntl
import os
import time

from raykit_grading.sandbox.workspace import PREFIX, Workspace, clean_stale


def test_a_killed_graders_workspace_is_removed_by_the_next_one(tmp_path):
    stale = tmp_path / f"{PREFIX}stale"
    stale.mkdir()
    (stale / ".lock").write_text("")
    (stale / "task-1").mkdir()
    busy = tmp_path / f"{PREFIX}busy"
    busy.mkdir()
    held = os.open(busy / ".lock", os.O_RDWR | os.O_CREAT)
    fcntl.flock(held, fcntl.LOCK_EX)  # a grader still running
    unlocked_old = tmp_path / f"{PREFIX}never-locked"
    unlocked_old.mkdir()
    os.utime(unlocked_old, (time.time() - 3600, time.time() - 3600))
    try:
        with Workspace(tmp_path) as mine:
            assert mine.is_dir() and (mine / ".lock").is_file()
            assert clean_stale(tmp_path) == []  # its own is locked
        assert not stale.exists() and not unlocked_old.exists() and busy.exists()
        assert not mine.exists()
    finally:
        os.close(held)

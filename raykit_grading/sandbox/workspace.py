"""The grader's own temporary folder: private, locked while in use, gone afterwards.

Each grading run makes ``<TMPDIR>/raykit-grading-XXXXXXXX`` (mode 700: no sandbox uid and no
other user may enter it) and holds an ``flock`` on ``.lock`` inside it for as long as it runs.
On leaving, the folder is removed. A grader that was killed cannot remove its folder; the next
grader started by the same user finds it unlocked and removes it (:func:`clean_stale`), so
nothing is left behind for long.

Removal is :func:`raykit_grading.sandbox.leftovers.remove_tree`'s, which never raises: whatever a
test's code left that still cannot be removed is moved into ``<TMPDIR>/raykit-grading-
quarantine`` (:func:`quarantine`) and named in one line on stderr, and the next grading starts
as if it were not there.
"""

from __future__ import annotations

import fcntl
import os
import stat
import sys
import tempfile
import time
from pathlib import Path

from raykit_grading.sandbox.leftovers import remove_tree

PREFIX = "raykit-grading-"


def quarantine(workspace: Path) -> Path:
    """Where what cannot be removed from under ``workspace`` is moved (same file system)."""
    return Path(workspace).parent / f"{PREFIX}quarantine"


def _remove(folder: Path) -> None:
    removal = remove_tree(folder, quarantine(folder))
    if removal.problem:
        print(f"raykit_grading: {removal.problem}", file=sys.stderr)


class Workspace:
    """``with Workspace() as folder:`` a private folder for one grading run."""

    def __init__(self, parent: Path | None = None) -> None:
        self.parent = Path(parent or tempfile.gettempdir())
        self.path: Path | None = None
        self._lock: int | None = None

    def __enter__(self) -> Path:
        clean_stale(self.parent)
        self.path = Path(tempfile.mkdtemp(prefix=PREFIX, dir=self.parent))
        # locked before it has its name, so that no other grader ever sees it unlocked
        self._lock = os.open(self.path / ".lock.new", os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o600)
        fcntl.flock(self._lock, fcntl.LOCK_EX)
        os.rename(self.path / ".lock.new", self.path / ".lock")
        return self.path

    def __exit__(self, *exc) -> None:
        _remove(self.path)
        os.close(self._lock)


def clean_stale(parent: Path) -> list[Path]:
    """Remove this user's grading folders whose grader is gone (their lock is free)."""
    removed = []
    for folder in parent.glob(f"{PREFIX}*"):
        if folder.name == quarantine(folder).name:
            continue
        try:
            info = os.lstat(folder)
        except OSError:
            continue
        if info.st_uid != os.geteuid() or not stat.S_ISDIR(info.st_mode):
            continue
        try:
            lock = os.open(folder / ".lock", os.O_RDWR | os.O_NOFOLLOW)
        except FileNotFoundError:  # never locked: a grader killed as it began, long ago
            if time.time() - info.st_mtime > 600:
                _remove(folder)
                removed.append(folder)
            continue
        except OSError:
            continue
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(lock)
            continue  # a grader is using it
        _remove(folder)
        os.close(lock)
        removed.append(folder)
    return removed

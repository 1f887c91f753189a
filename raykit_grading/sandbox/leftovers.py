"""What a test's code leaves on disk: measured against its budget, and removed whatever it is.

A test's child may write in one folder only, its ``tmp/``. What it leaves there is hostile: any
number of entries, nested any depth (deeper than a path can name), closed to its owner (mode
000), links, FIFOs, sockets. Two things are done with it, neither of which can raise:

* :func:`measure`, while the child runs and after: its bytes (blocks really held, so a sparse
  file costs what it holds) and entries against :class:`DiskBudget`, stopping as soon as the
  budget is passed, so a walk costs at most the budget however much is there; it never holds
  more than :attr:`DiskBudget.depth` folders open.
* :func:`remove_tree`, after the child and every process of its uid are dead: a walk of the
  grader's own, in constant depth (every folder found is first moved up into one holding folder,
  so nothing is ever more than two levels deep and no path is ever long) and without recursion,
  within a time bound. What still cannot be removed is moved aside into a quarantine folder
  and reported, never raised.
"""

from __future__ import annotations

import errno
import os
import secrets
import stat
import time
from dataclasses import dataclass
from pathlib import Path

DIRECTORY = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC
# measured while the child runs, so every step is by a handle, never a path it could swap


@dataclass(frozen=True)
class DiskBudget:
    """What a test's ``tmp/`` may hold at once: bytes (blocks held), entries (files, folders,
    links of any kind) and how deep its folders nest."""

    bytes: int = 64 * 2**20
    entries: int = 4096
    depth: int = 32

    def describe(self) -> str:
        return (
            f"{self.bytes // 2**20} MB, {self.entries} files and folders, folders {self.depth} deep"
        )


def measure(folder: Path, budget: DiskBudget, already: int = 0) -> str:
    """ "" if ``folder`` is within ``budget``, ``already`` bytes held elsewhere counted with
    it (the files with no name a test's process holds); else what it passed, in words."""
    if already > budget.bytes:
        return f"more than {budget.bytes // 2**20} MB"
    try:
        top = os.open(folder, DIRECTORY)
    except OSError:
        return ""  # nothing there (or not a folder the child could fill)
    held, entries = already, 0
    stack = [(top, iter(_names(top)))]  # open folders, at most budget.depth of them
    try:
        while stack:
            fd, names = stack[-1]
            name = next(names, None)
            if name is None:
                os.close(stack.pop()[0])
                continue
            entries += 1
            if entries > budget.entries:
                return f"more than {budget.entries} files and folders"
            try:
                info = os.stat(name, dir_fd=fd, follow_symlinks=False)
            except OSError:
                continue
            held += info.st_blocks * 512
            if held > budget.bytes:
                return f"more than {budget.bytes // 2**20} MB"
            if stat.S_ISDIR(info.st_mode):
                if len(stack) >= budget.depth:
                    return f"folders more than {budget.depth} deep"
                inner = _open_to_count(fd, name)
                if inner is None:
                    return "a folder the grader cannot look into"
                stack.append((inner, iter(_names(inner))))
        return ""
    finally:
        for fd, _ in stack:
            os.close(fd)


def _open_to_count(fd: int, name: str) -> int | None:
    """A folder of the child's, opened to be counted; one its owner closed (mode 000) is
    opened again to its owner first, as the grader as a normal user is that owner (root needs
    no such thing). None if it cannot be."""
    try:
        return os.open(name, DIRECTORY, dir_fd=fd)
    except PermissionError:
        pass
    except OSError:
        return None  # gone meanwhile, or made something else: nothing to count
    try:  # by a handle on that very folder: the child may swap the name for a link meanwhile
        handle = os.open(name, os.O_PATH | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=fd)
    except OSError:
        return None
    try:
        os.chmod(f"/proc/self/fd/{handle}", 0o700)
        # the handle's link in /proc is the folder itself, so it is followed (no O_NOFOLLOW)
        return os.open(f"/proc/self/fd/{handle}", os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        return None
    finally:
        os.close(handle)


def _names(fd: int) -> list[str]:
    try:
        return os.listdir(fd)
    except OSError:
        return []


@dataclass
class Removal:
    """What :func:`remove_tree` did: ``entries`` removed, ``forced`` what it had to force
    (folders closed to their owner, special files), and where what was left went."""

    entries: int = 0
    forced: set[str] | None = None
    left_in: Path | None = None
    problem: str = ""


def remove_tree(path: Path, quarantine: Path | None = None, seconds: float = 60.0) -> Removal:
    """Remove ``path`` (a folder or anything else) and all in it; never raises.

    The folder is first renamed to a holding name beside it; then each folder found inside is
    moved up into the holding folder under a name of ours before it is emptied, so the walk
    never goes more than one level down and never names a long path. After ``seconds``, or if
    something cannot be removed, what is left is moved into ``quarantine`` (a folder of the
    grader's on the same file system; made if missing) and reported in :attr:`Removal.problem`.
    """
    done = Removal(forced=set())
    path = Path(path)
    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return done
    except OSError as exc:
        done.problem = f"cannot look at {path}: {exc.strerror}"
        return done
    if not stat.S_ISDIR(info.st_mode):
        try:
            os.unlink(path)
            done.entries = 1
        except OSError as exc:
            done.problem = f"cannot remove {path}: {exc.strerror}"
        return done
    holding = path.with_name(f".removing-{secrets.token_hex(6)}")
    try:
        os.rename(path, holding)
    except OSError as exc:
        done.problem = f"cannot move {path} aside: {exc.strerror}"
        return done
    deadline = time.monotonic() + seconds
    try:
        _empty(holding, done, deadline)
        os.rmdir(holding)
        return done
    except Exception as exc:  # noqa: BLE001 - nothing a child left may stop the grader
        reason = "it took too long" if isinstance(exc, TimeoutError) else _says(exc)
    done.left_in = _set_aside(holding, quarantine)
    where = f"moved to {done.left_in}" if done.left_in else f"left in {holding}"
    done.problem = f"could not remove everything in {path} ({reason}): {where}"
    return done


def _empty(holding: Path, done: Removal, deadline: float) -> None:
    """Empty ``holding`` by moving every folder in it up to its top level, then emptying
    those one level at a time."""
    try:
        top = os.open(holding, DIRECTORY)
    except PermissionError:  # the folder itself closed by its owner
        os.chmod(holding, 0o700)
        top = os.open(holding, DIRECTORY)
    try:
        os.fchmod(top, 0o700)
        pending = [name for name in os.listdir(top) if _is_folder(top, name)]
        _unlink_all_but(top, set(pending), done)
        made = 0
        while pending:
            if time.monotonic() > deadline:
                raise TimeoutError
            name = pending.pop()
            inner = _open_folder(top, name, done)
            try:
                for entry in os.listdir(inner):
                    mode = os.stat(entry, dir_fd=inner, follow_symlinks=False).st_mode
                    if stat.S_ISDIR(mode):
                        if mode & 0o700 != 0o700:  # moving a folder rewrites its ".."
                            os.chmod(entry, 0o700, dir_fd=inner)
                            done.forced.add("folders closed to their owner")
                        made += 1
                        moved = f"d{made}"
                        os.rename(entry, moved, src_dir_fd=inner, dst_dir_fd=top)
                        pending.append(moved)
                    else:
                        _unlink(inner, entry, done)
            finally:
                os.close(inner)
            os.rmdir(name, dir_fd=top)
            done.entries += 1
    finally:
        os.close(top)


def _is_folder(fd: int, name: str) -> bool:
    return stat.S_ISDIR(os.stat(name, dir_fd=fd, follow_symlinks=False).st_mode)


def _open_folder(top: int, name: str, done: Removal) -> int:
    try:
        inner = os.open(name, DIRECTORY, dir_fd=top)
    except PermissionError:  # closed by its owner, the grader's uid (a normal user's grading)
        os.chmod(name, 0o700, dir_fd=top)
        done.forced.add("folders closed to their owner")
        inner = os.open(name, DIRECTORY, dir_fd=top)
    if stat.S_IMODE(os.fstat(inner).st_mode) & 0o700 != 0o700:
        os.fchmod(inner, 0o700)  # a folder its owner may not write: its entries unlinkable
        done.forced.add("folders closed to their owner")
    return inner


def _unlink_all_but(fd: int, keep: set[str], done: Removal) -> None:
    for name in os.listdir(fd):
        if name not in keep:
            _unlink(fd, name, done)


def _unlink(fd: int, name: str, done: Removal) -> None:
    mode = os.stat(name, dir_fd=fd, follow_symlinks=False).st_mode
    if not (stat.S_ISREG(mode) or stat.S_ISLNK(mode)):
        done.forced.add("special files (FIFOs, sockets or devices)")
    os.unlink(name, dir_fd=fd)
    done.entries += 1


def _says(exc: BaseException) -> str:
    if isinstance(exc, OSError) and exc.errno is not None:
        return errno.errorcode.get(exc.errno, str(exc.errno))
    return type(exc).__name__


def _set_aside(holding: Path, quarantine: Path | None) -> Path | None:
    if quarantine is None:
        return None
    try:
        quarantine.mkdir(mode=0o700, parents=True, exist_ok=True)
        target = quarantine / f"{time.strftime('%Y%m%dT%H%M%S')}-{secrets.token_hex(4)}"
        os.rename(holding, target)
        return target
    except OSError:
        return None

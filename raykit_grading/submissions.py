"""Taking in a submission: its ``raykit`` package copied as plain files, never followed.

A submission is hostile input on disk. :func:`stage` copies its ``raykit/`` package (at the
top of the submission, one folder down, or inside a ``.zip`` there) into the grader's own
workspace before anything runs, and every later step reads only that copy:

* only regular files and folders are copied, each opened relative to its folder's descriptor
  with ``O_NOFOLLOW | O_NONBLOCK`` and checked with ``fstat``: a symbolic link (to the reference
  package, to a root-only file), a FIFO, a socket or a device is left out and named in the
  feedback, never followed, never read, never waited on;
* sizes are bounded (:data:`MAX_FILES` files, :data:`MAX_BYTES` bytes, :data:`MAX_DEPTH`
  folders deep), for a zip before anything is inflated;
* a zip's member names may not leave the folder (``..``, absolute paths), its links are left
  out.
"""

from __future__ import annotations

import os
import stat
import zipfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

MAX_FILES = 1000
MAX_BYTES = 32 * 1024**2
MAX_DEPTH = 12
PACKAGE = "raykit"


@dataclass
class Staged:
    """The staged copy: ``root`` holds ``raykit/`` (``package`` is None if none was found)."""

    root: Path
    package: Path | None
    notes: list[str] = field(default_factory=list)
    files: int = 0
    size: int = 0


class SubmissionError(ValueError):
    """The submission cannot be taken in (the message says why, for the student)."""


def stage(submission: Path, root: Path) -> Staged:
    """Copy the submission's ``raykit`` package into ``root`` (a new folder), safely."""
    root.mkdir(mode=0o755)
    staged = Staged(root, None)
    try:
        top = os.open(submission, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
    except OSError as exc:
        raise SubmissionError(f"{submission}: not a folder ({exc.strerror})") from None
    try:
        source = _find_package(top, staged)
        if source is not None:
            _copy_folder(source, root / PACKAGE, staged, PACKAGE, 0)
            os.close(source)
        else:
            archives = [n for n in sorted(os.listdir(top)) if n.lower().endswith(".zip")]
            for name in archives[:1]:
                _unzip(top, name, root, staged)
    finally:
        os.close(top)
    package = root / PACKAGE
    if _is_real_file(package / "__init__.py"):
        staged.package = package
    for path in [root, *root.rglob("*")]:  # readable by the sandbox user, writable by none
        os.chmod(path, 0o755 if path.is_dir() else 0o644)
    return staged


def _is_real_file(path: Path) -> bool:
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def _kind(fd: int, name: str) -> int:
    return os.stat(name, dir_fd=fd, follow_symlinks=False).st_mode


def _find_package(top: int, staged: Staged) -> int | None:
    """A descriptor of ``raykit/`` at the top or one folder down (a real folder, not a link);
    folders are looked into one at a time, so a submission of many folders opens few files."""
    found = _package_in(top, PACKAGE, staged)
    if found is not None:
        return found
    for name in sorted(os.listdir(top)):
        try:
            if name == PACKAGE or not stat.S_ISDIR(_kind(top, name)):
                continue
            inner = os.open(name, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=top)
        except OSError:
            continue
        try:
            found = _package_in(inner, f"{_shown(name)}/{PACKAGE}", staged)
        finally:
            os.close(inner)
        if found is not None:
            return found
    return None


def _package_in(folder: int, shown: str, staged: Staged) -> int | None:
    try:
        mode = _kind(folder, PACKAGE)
    except OSError:
        return None
    if stat.S_ISLNK(mode):
        staged.notes.append(f"{shown} is a symbolic link: not followed (submit the folder)")
    elif stat.S_ISDIR(mode):
        try:
            return os.open(PACKAGE, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=folder)
        except OSError as exc:
            staged.notes.append(f"{shown} could not be opened ({exc.strerror})")
    return None


def _shown(name: str) -> str:
    """A file name as text that any JSON reader takes (undecodable bytes escaped)."""
    return name.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


def _copy_folder(source: int, target: Path, staged: Staged, shown: str, depth: int) -> None:
    if depth > MAX_DEPTH:
        raise SubmissionError(f"{shown}: folders nested more than {MAX_DEPTH} deep")
    target.mkdir(mode=0o755)
    try:
        names = sorted(os.listdir(source))
    except OSError as exc:
        staged.notes.append(f"{shown} could not be read ({exc.strerror}): left out")
        return
    for name in names:
        if name == "__pycache__":
            continue
        where = f"{shown}/{_shown(name)}"
        try:
            mode = _kind(source, name)
        except OSError:
            continue
        if stat.S_ISDIR(mode):
            try:
                inner = os.open(name, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=source)
            except OSError as exc:
                staged.notes.append(f"{where} could not be read ({exc.strerror}): left out")
                continue
            try:
                _copy_folder(inner, target / name, staged, where, depth + 1)
            finally:
                os.close(inner)
        elif stat.S_ISREG(mode):
            _copy_file(source, name, target / name, staged, where)
        else:
            staged.notes.append(f"{where} is {_describe(mode)}: left out (only plain files count)")


def _copy_file(folder: int, name: str, target: Path, staged: Staged, shown: str) -> None:
    try:
        fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK, dir_fd=folder)
    except OSError as exc:
        staged.notes.append(f"{shown}: could not be read ({exc.strerror}): left out")
        return
    with os.fdopen(fd, "rb") as stream:
        info = os.fstat(stream.fileno())
        if not stat.S_ISREG(info.st_mode):  # swapped since it was listed
            staged.notes.append(f"{shown} is {_describe(info.st_mode)}: left out")
            return
        _count(staged, info.st_size, shown)
        data = stream.read(info.st_size + 1)
    if len(data) > info.st_size:
        raise SubmissionError(f"{shown}: grew while it was copied")
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW
    try:
        with open(os.open(target, flags, 0o644), "wb") as out:
            out.write(data)
    except OSError as exc:
        staged.notes.append(f"{shown} could not be copied ({exc.strerror}): left out")


def _count(staged: Staged, size: int, shown: str) -> None:
    staged.files += 1
    staged.size += size
    if staged.files > MAX_FILES:
        raise SubmissionError(f"more than {MAX_FILES} files in the submission")
    if staged.size > MAX_BYTES:
        raise SubmissionError(f"the submission is larger than {MAX_BYTES // 2**20} MB (at {shown})")


def _unzip(top: int, name: str, root: Path, staged: Staged) -> None:
    """The ``raykit/`` package inside a zip at the submission's top (as Gradescope keeps it)."""
    mode = _kind(top, name)
    if not stat.S_ISREG(mode):
        staged.notes.append(f"{name} is {_describe(mode)}: left out")
        return
    fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK, dir_fd=top)
    with os.fdopen(fd, "rb") as stream:
        if os.fstat(stream.fileno()).st_size > MAX_BYTES:
            raise SubmissionError(f"{name} is larger than {MAX_BYTES // 2**20} MB")
        try:
            archive = zipfile.ZipFile(stream)
        except zipfile.BadZipFile:
            raise SubmissionError(f"{name} is not a zip file") from None
        with archive:
            members = []
            for member in archive.infolist():
                parts = PurePosixPath(member.filename).parts
                inside = [i for i, part in enumerate(parts) if part == PACKAGE]
                if member.is_dir() or not inside or "__pycache__" in parts:
                    continue
                if ".." in parts or member.filename.startswith("/"):
                    raise SubmissionError(f"{name}: {member.filename} leaves the folder")
                if stat.S_ISLNK(member.external_attr >> 16):
                    staged.notes.append(f"{name}: {_shown(member.filename)} is a link: left out")
                    continue
                members.append((member, parts[inside[0] :]))
            if sum(m.file_size for m, _ in members) > MAX_BYTES or len(members) > MAX_FILES:
                raise SubmissionError(f"{name} unpacks to more than {MAX_BYTES // 2**20} MB")
            for member, parts in members:
                _unzip_member(archive, member, parts, root, staged, name)


def _unzip_member(archive, member, parts, root: Path, staged: Staged, name: str) -> None:
    shown = _shown("/".join(parts))
    target = root.joinpath(*parts)
    if len(parts) > MAX_DEPTH or os.path.lexists(target):
        return
    try:
        target.parent.mkdir(parents=True, exist_ok=True, mode=0o755)
        with archive.open(member) as data:
            content = data.read(member.file_size + 1)
        _count(staged, len(content), shown)
        flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW
        with open(os.open(target, flags, 0o644), "wb") as out:
            out.write(content[: member.file_size])
    except SubmissionError:
        raise
    except OSError as exc:  # a name too long, a file where a folder should be, ...
        staged.notes.append(f"{name}: {shown} could not be unpacked ({exc.strerror}): left out")
    except Exception as exc:  # noqa: BLE001 - a damaged, encrypted or exotic member
        raise SubmissionError(
            f"{_shown(name)}: {shown} cannot be unpacked ({type(exc).__name__}: {exc})"
        ) from None


def _describe(mode: int) -> str:
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a plain file"

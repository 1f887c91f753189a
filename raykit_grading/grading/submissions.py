"""Taking in a submission: its ``raykit`` package copied as plain files, never followed.

A submission is hostile input on disk. :func:`stage` copies its ``raykit/`` package into the
grader's own workspace before anything runs, and every later step reads only that copy.

What students are asked to upload is the ``raykit/`` folder, or a zip of it. The common wrong
shapes are recognised, each with one line saying what was found and what was expected: a
``raykit/`` one or more folders too deep (``myname/raykit/``, in a folder or a zip) or in a zip
inside a zip is graded, with a note, when it is the only one that near the top; several of
them, loose Python files, a ``raykit`` link or a ``raykit/`` without ``__init__.py`` are told
so (``Staged.problem``) and nothing is graded. Taking the package in:

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

import contextlib
import io
import os
import stat
import zipfile
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath

MAX_FILES = 1000
MAX_BYTES = 32 * 1024**2
MAX_DEPTH = 12
PACKAGE = "raykit"
SEARCH_DEPTH = 3  # folders down from the top that a misplaced raykit/ is looked for in
SEARCH_FOLDERS = 200  # folders opened in that search, at most
MAX_ZIPS = 4  # zips looked into, at the top (and in a zip)
UPLOAD = "upload your raykit/ folder itself, or a zip of it"


@dataclass
class Staged:
    """The staged copy: ``root`` holds ``raykit/`` (``package`` is None if none was found)."""

    root: Path
    package: Path | None
    notes: list[str] = field(default_factory=list)
    files: int = 0
    size: int = 0
    problem: str | None = None  # why there is no package: what was found, what was expected


class SubmissionError(ValueError):
    """The submission cannot be taken in (the message says why, for the student)."""


def stage(submission: Path, root: Path) -> Staged:
    """Copy the submission's ``raykit`` package into ``root`` (a new folder), safely; when
    there is none, ``Staged.problem`` says what was found instead."""
    root.mkdir(mode=0o755)
    staged = Staged(root, None)
    try:
        top = os.open(submission, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
    except OSError as exc:
        raise SubmissionError(f"{submission}: not a folder ({exc.strerror})") from None
    try:
        survey = _survey_folder(top)
        staged.notes += [f"{link} is a symbolic link: not followed (submit the folder)"
                         for link in survey.links]  # fmt: skip
        chosen = _shallowest(survey.candidates)
        if chosen is not None and len(chosen) == 1:
            parts, shown = chosen[0]
            source = _open_path(top, parts)
            if source is not None:
                try:
                    _copy_folder(source, root / PACKAGE, staged, PACKAGE, 0)
                finally:
                    os.close(source)
                if len(parts) > 1:
                    staged.notes.append(f"found {shown}/ (expected raykit/ at the top of the "
                                        "submission): graded it")  # fmt: skip
        elif chosen is not None:
            staged.problem = _several(chosen)
        else:
            _from_zips(top, survey, root, staged)
        if staged.problem is None and not _is_real_file(root / PACKAGE / "__init__.py"):
            staged.problem = _what_was_found(survey)
    finally:
        os.close(top)
    package = root / PACKAGE
    if staged.problem is None and _is_real_file(package / "__init__.py"):
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


@dataclass
class _Survey:
    """What a submission holds, as far as finding its ``raykit/`` goes."""

    candidates: list[tuple[tuple[str, ...], str]] = field(default_factory=list)  # parts, shown
    links: list[str] = field(default_factory=list)  # raykit entries that are symbolic links
    without_init: list[str] = field(default_factory=list)  # raykit/ with no __init__.py
    top: list[str] = field(default_factory=list)  # the names at the top
    loose: list[str] = field(default_factory=list)  # Python files at the top (or a zip's)
    loose_in: str = ""  # " in raykit.zip": where the loose files are
    zips: list[str] = field(default_factory=list)  # zips at the top
    nested: list[str] = field(default_factory=list)  # zips in zips, found without a raykit/


def _survey_folder(top: int) -> _Survey:
    """Every ``raykit/`` up to :data:`SEARCH_DEPTH` folders down (a real folder holding a real
    ``__init__.py``; links are noted, never followed), breadth first, opening at most
    :data:`SEARCH_FOLDERS` folders."""
    survey = _Survey()
    queue: list[tuple[int, tuple[str, ...]]] = [(top, ())]
    opened = 0
    while queue:
        folder, parts = queue.pop(0)
        try:
            names = sorted(os.listdir(folder))
        except OSError:
            names = []
        for name in names:
            try:
                mode = _kind(folder, name)
            except OSError:
                continue
            shown = "/".join(_shown(p) for p in (*parts, name))
            if not parts:
                survey.top.append(shown)
                if stat.S_ISREG(mode) and name.lower().endswith(".py"):
                    survey.loose.append(shown)
                if stat.S_ISREG(mode) and name.lower().endswith(".zip"):
                    survey.zips.append(name)
            if name == PACKAGE:
                if stat.S_ISLNK(mode):
                    survey.links.append(shown)
                elif stat.S_ISDIR(mode):
                    if _holds_init(folder):
                        survey.candidates.append(((*parts, name), shown))
                    else:
                        survey.without_init.append(f"{shown}/")
                continue
            if (
                stat.S_ISDIR(mode)
                and len(parts) < SEARCH_DEPTH
                and not _skipped(name)
                and opened < SEARCH_FOLDERS
            ):
                try:
                    inner = os.open(name, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW,
                                    dir_fd=folder)  # fmt: skip
                except OSError:
                    continue
                opened += 1
                queue.append((inner, (*parts, name)))
        if folder != top:
            os.close(folder)
    return survey


def _skipped(name: str) -> bool:
    """Folders never searched: hidden ones (.git, .venv), macOS's __MACOSX, caches."""
    return name.startswith(".") or name in ("__MACOSX", "__pycache__", "site-packages")


def _holds_init(folder: int) -> bool:
    try:
        package = os.open(PACKAGE, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=folder)
    except OSError:
        return False
    try:
        return stat.S_ISREG(_kind(package, "__init__.py"))
    except OSError:
        return False
    finally:
        os.close(package)


def _open_path(top: int, parts: tuple[str, ...]) -> int | None:
    """A descriptor of the folder at ``parts`` below ``top``, no link followed on the way."""
    folder = top
    for name in parts:
        try:
            inner = os.open(name, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW, dir_fd=folder)
        except OSError:
            inner = None
        if folder != top:
            os.close(folder)
        if inner is None:
            return None
        folder = inner
    return folder


def _shallowest(candidates: list) -> list | None:
    """The candidates nearest the top (None if there are none): one is the package, several
    are a question the grader does not guess the answer to."""
    if not candidates:
        return None
    depth = min(len(parts) for parts, _ in candidates)
    return [c for c in candidates if len(c[0]) == depth]


def _listed(names: list[str], most: int = 4) -> str:
    shown = ", ".join(names[:most])
    return f"{shown} and {len(names) - most} more" if len(names) > most else shown


def _several(chosen: list) -> str:
    return (f"no raykit package: found {len(chosen)} raykit/ folders "
            f"({_listed([f'{shown}/' for _, shown in chosen])}); expected one, at the top of "
            f"the submission: {UPLOAD}")  # fmt: skip


def _what_was_found(survey: _Survey) -> str:
    """The one line a submission with no ``raykit/`` package gets: what it holds instead."""
    if survey.nested:
        found = f"only zips inside zips ({_listed(survey.nested)})"
    elif survey.links:
        found = f"{survey.links[0]} as a symbolic link (links are not followed)"
    elif survey.without_init:
        found = f"{survey.without_init[0]} without an __init__.py"
    elif survey.loose:
        found = (f"loose Python files{survey.loose_in} ({_listed(survey.loose)}) instead of "
                 "the raykit/ folder that holds them")  # fmt: skip
    elif survey.zips:
        found = f"no raykit/ folder in {_listed(survey.zips)}"
    elif survey.top:
        found = f"no raykit/ folder, only {_listed(survey.top)}"
    else:
        found = "an empty submission"
    return f"no raykit package: found {found}; expected raykit/__init__.py: {UPLOAD}"


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


def _from_zips(top: int, survey: _Survey, root: Path, staged: Staged) -> None:
    """The ``raykit/`` package inside a zip at the submission's top (as Gradescope may keep an
    upload), or inside a zip in that zip; several zips holding one are refused."""
    found = []  # (where, archive, prefix of raykit/ in it)
    with contextlib.ExitStack() as opened:
        for name in survey.zips[:MAX_ZIPS]:
            archive = opened.enter_context(_open_zip(top, name))
            if archive is None:
                staged.notes.append(f"{_shown(name)} is not a plain file: left out")
                continue
            _refuse_escapes(archive, _shown(name))
            chosen = _shallowest(_zip_candidates(archive))
            if chosen is None:
                survey.without_init += _zip_without_init(archive, _shown(name))
            if chosen is None and not survey.loose:
                survey.loose = sorted(_shown(m) for m in _loose(archive))
                survey.loose_in = f" in {_shown(name)}" if survey.loose else ""
            if chosen is None:  # a zip of a zip: its zips, one level down
                for inner_name, inner in _inner_zips(archive, name, opened):
                    where = f"{_shown(inner_name)} inside {_shown(name)}"
                    _refuse_escapes(inner, where)
                    chosen = _shallowest(_zip_candidates(inner))
                    if chosen is None:
                        survey.nested += [f"{_shown(z)} inside {where}" for z in _zip_names(inner)]
                    elif len(chosen) > 1:
                        staged.problem = _several(chosen)
                    else:
                        found.append((where, inner, chosen[0][0], True))
            elif len(chosen) > 1:
                staged.problem = _several(chosen)
            else:
                found.append((_shown(name), archive, chosen[0][0], False))
        if staged.problem is not None:
            return
        if len(found) > 1:
            staged.problem = (f"no raykit package: found raykit/ in {len(found)} zips "
                              f"({_listed([where for where, *_ in found])}); expected one: "
                              f"{UPLOAD}")  # fmt: skip
            return
        for where, archive, prefix, nested in found:
            _unzip(archive, prefix, where, root, staged)
            inside = "/".join(prefix)
            if nested:
                staged.notes.append(f"found raykit/ in {where} (a zip of a zip; expected the "
                                    "raykit/ folder or one zip of it): graded it")  # fmt: skip
            elif inside:
                staged.notes.append(f"found {_shown(inside)}/raykit/ in {where} (expected "
                                    "raykit/ at the top of the zip): graded it")  # fmt: skip


@contextlib.contextmanager
def _open_zip(top: int, name: str):
    """A zip at the submission's top, opened (None if it is not a plain file)."""
    if not stat.S_ISREG(_kind(top, name)):
        yield None
        return
    fd = os.open(name, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK, dir_fd=top)
    with os.fdopen(fd, "rb") as stream:
        info = os.fstat(stream.fileno())
        if not stat.S_ISREG(info.st_mode):
            yield None
            return
        if info.st_size > MAX_BYTES:
            raise SubmissionError(f"{_shown(name)} is larger than {MAX_BYTES // 2**20} MB")
        try:
            archive = zipfile.ZipFile(stream)
        except zipfile.BadZipFile:
            raise SubmissionError(f"{_shown(name)} is not a zip file") from None
        with archive:
            yield archive


def _member_parts(member: zipfile.ZipInfo) -> tuple[str, ...]:
    return PurePosixPath(member.filename).parts


def _refuse_escapes(archive: zipfile.ZipFile, where: str) -> None:
    """A zip whose member names would leave the folder is refused whole (hostile, not lost)."""
    for member in archive.infolist():
        if ".." in _member_parts(member) or member.filename.startswith("/"):
            raise SubmissionError(f"{where}: {_shown(member.filename)} leaves the folder")


def _zip_without_init(archive: zipfile.ZipFile, where: str) -> list[str]:
    """The ``raykit/`` folders in a zip that hold no ``__init__.py``."""
    names = {_member_parts(m) for m in archive.infolist()}
    found = []
    for parts in sorted(names):
        if PACKAGE in parts[:-1] and not any(_skipped(p) for p in parts):
            prefix = parts[: parts.index(PACKAGE) + 1]
            shown = f"{_shown('/'.join(prefix))}/ in {where}"
            if (*prefix, "__init__.py") not in names and shown not in found:
                found.append(shown)
    return found


def _zip_candidates(archive: zipfile.ZipFile) -> list[tuple[tuple[str, ...], str]]:
    """Where ``raykit/__init__.py`` sits in a zip, up to :data:`SEARCH_DEPTH` folders down."""
    found = []
    for member in archive.infolist():
        parts = _member_parts(member)
        if (
            parts[-2:] == (PACKAGE, "__init__.py")
            and len(parts) - 2 <= SEARCH_DEPTH
            and not member.is_dir()
            and not any(_skipped(p) for p in parts[:-2] if p != "..")
        ):
            prefix = parts[:-2]
            found.append((prefix, _shown("/".join((*prefix, PACKAGE)))))
    return found


def _loose(archive: zipfile.ZipFile) -> list[str]:
    """Python files at a zip's top, or in its one top folder: raykit's files, zipped loose."""
    return [
        m.filename
        for m in archive.infolist()
        if m.filename.lower().endswith(".py")
        and len(_member_parts(m)) <= 2
        and not any(_skipped(p) for p in _member_parts(m))
    ]


def _zip_names(archive: zipfile.ZipFile) -> list[str]:
    return [
        m.filename
        for m in archive.infolist()
        if m.filename.lower().endswith(".zip")
        and not m.is_dir()
        and len(_member_parts(m)) <= SEARCH_DEPTH + 1
        and not any(_skipped(p) for p in _member_parts(m))
    ]


def _inner_zips(archive: zipfile.ZipFile, name: str, opened: contextlib.ExitStack):
    """The zips inside a zip, each read (bounded) and opened."""
    for inner_name in _zip_names(archive)[:MAX_ZIPS]:
        member = archive.getinfo(inner_name)
        if member.file_size > MAX_BYTES:
            raise SubmissionError(f"{_shown(name)}: {_shown(inner_name)} is larger than "
                                  f"{MAX_BYTES // 2**20} MB")  # fmt: skip
        try:
            with archive.open(member) as data:
                content = data.read(MAX_BYTES + 1)
            inner = zipfile.ZipFile(io.BytesIO(content))
        except zipfile.BadZipFile:
            continue  # a file named .zip that is none: not where raykit/ is
        except Exception as exc:  # noqa: BLE001 - a damaged, encrypted or exotic member
            raise SubmissionError(
                f"{_shown(name)}: {_shown(inner_name)} cannot be unpacked "
                f"({type(exc).__name__}: {exc})"
            ) from None
        yield inner_name, opened.enter_context(inner)


def _unzip(
    archive: zipfile.ZipFile, prefix: tuple[str, ...], where: str, root: Path, staged: Staged
) -> None:
    """The zip's ``<prefix>/raykit/`` unpacked into ``root/raykit/``: plain files only, names
    that stay inside the folder, within bounds."""
    start = len(prefix)
    members = []
    for member in archive.infolist():
        parts = _member_parts(member)
        if member.is_dir() or parts[: start + 1] != (*prefix, PACKAGE) or "__pycache__" in parts:
            continue
        if ".." in parts or member.filename.startswith("/"):
            raise SubmissionError(f"{where}: {_shown(member.filename)} leaves the folder")
        if stat.S_ISLNK(member.external_attr >> 16):
            staged.notes.append(f"{where}: {_shown(member.filename)} is a link: left out")
            continue
        members.append((member, parts[start:]))
    if sum(m.file_size for m, _ in members) > MAX_BYTES or len(members) > MAX_FILES:
        raise SubmissionError(f"{where} unpacks to more than {MAX_BYTES // 2**20} MB")
    for member, parts in members:
        _unzip_member(archive, member, parts, root, staged, where)


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

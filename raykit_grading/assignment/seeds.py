"""One secret seed per assignment: every student, every command and every regrade get the same
graded inputs.

The graded inputs (:meth:`raykit_grading.assignment.catalog.GradingTest.graded_inputs`) are drawn
from a seed, made once per assignment and kept in the instructor's *assignment folder* as
``grading-seed`` (mode 600; only the instructor, and the grader as root, can read it). Every
command that makes or grades the assignment (``release``, ``gradescope``, ``grade``, ``batch``,
``try-zip``) calls :func:`assignment_seed`, which finds it:

* ``--seed N``: that seed (kept in no file);
* ``--seed-file PATH``: the seed in PATH (made there if missing);
* ``--assignment DIR``: ``DIR/grading-seed`` (made there if missing, by the commands that make);
* else the first ``grading-seed`` in the current folder or one of its parents, as git finds
  ``.git`` (:func:`find_assignment`): the search stops below your home folder and the
  filesystem's root, and at a mount point; if there is none, the commands that make one make it
  in the current folder.

Each command prints the seed's :func:`fingerprint` and its file in one line on stderr
(:meth:`AssignmentSeed.line`). ``gradescope`` copies the seed into the zip (``grading-seed`` at
its top, closed to root by ``setup.sh``), and the zip's ``run_autograder`` grades under it. A
seed file is made with mode 600, atomically (two commands starting at once read the same seed).
results.json names the seed by its fingerprint only: hidden results are shown to students after
the due date, and a student who knew the seed could draw the hidden tests' inputs for a regrade.
"""

from __future__ import annotations

import hashlib
import os
import secrets
import stat
import sys
from dataclasses import dataclass
from pathlib import Path

SEED_BITS = 128  # too many to try them all against a fingerprint
FILE_NAME = "grading-seed"
HEADER = (
    "# raykit grading seed: every graded input of this assignment is drawn from it.\n"
    "# Keep it secret (mode 600): whoever reads it can draw the hidden tests' inputs.\n"
)


class SeedFileError(ValueError):
    """A seed file that cannot be read or made (the message names the file and why)."""


def new_seed() -> int:
    return secrets.randbits(SEED_BITS)


def fingerprint(seed: int) -> str:
    """A name for ``seed`` that does not give it away (a hash: two gradings under the same
    seed carry the same fingerprint)."""
    digest = hashlib.sha256(f"raykit grading seed {seed}".encode()).hexdigest()
    return f"sha256:{digest[:16]}"


def read_seed_file(path: Path) -> int:
    """The seed in ``path``: one whole number >= 0 (lines starting with # are comments)."""
    path = Path(path)
    try:
        with open(path, encoding="utf-8") as stream:
            info = os.fstat(stream.fileno())
            if not stat.S_ISREG(info.st_mode):
                raise SeedFileError(f"{path}: not a plain file")
            text = stream.read(4096)
    except OSError as exc:
        raise SeedFileError(f"{path}: cannot be read ({exc.strerror})") from None
    except UnicodeDecodeError:
        raise SeedFileError(f"{path}: not a grading seed (not text)") from None
    seed = parse_seed(text, path)
    if info.st_mode & 0o077:
        _close_to_others(path, info)
    return seed


def parse_seed(text: str, where: Path | str) -> int:
    """The seed a seed file's ``text`` holds (read from ``where``, which errors name)."""
    words = [w for line in text.splitlines() if not line.lstrip().startswith("#")
             for w in line.split()]  # fmt: skip
    if len(words) != 1 or not (words[0].isascii() and words[0].isdigit()):
        raise SeedFileError(f"{where}: not a grading seed (expected one whole number >= 0)")
    return int(words[0])


def _close_to_others(path: Path, info: os.stat_result) -> None:
    """A seed file others may read: made private if it is ours, else a warning."""
    if info.st_uid == os.geteuid():
        os.chmod(path, 0o600)
        print(f"raykit_grading: note: {path} was readable by others: made it mode 600",
              file=sys.stderr)  # fmt: skip
    else:
        print(f"raykit_grading: warning: {path} is readable by others (mode "
              f"{stat.S_IMODE(info.st_mode):o}): keep it secret", file=sys.stderr)  # fmt: skip


def seed_from_file(path: Path) -> tuple[int, bool]:
    """The seed in ``path``, made first (mode 600) if there is no such file: (seed, made)."""
    path = Path(path)
    if os.path.lexists(path):
        return read_seed_file(path), False
    if not path.parent.is_dir():
        raise SeedFileError(f"{path}: its folder {path.parent} does not exist")
    seed = new_seed()
    temporary = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}")
    try:
        fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
        with os.fdopen(fd, "w", encoding="utf-8") as stream:
            stream.write(f"{HEADER}{seed}\n")
            stream.flush()
            os.fsync(stream.fileno())
        try:
            os.link(temporary, path)  # never replaces a seed another grader made meanwhile
        except FileExistsError:
            return read_seed_file(path), False
    except OSError as exc:
        raise SeedFileError(f"{path}: cannot be made ({exc.strerror})") from None
    finally:
        temporary.unlink(missing_ok=True)
    return seed, True


def seed_argument(text: str) -> int:
    """``--seed``: a whole number >= 0 (argparse type)."""
    import argparse

    if not (text.isascii() and text.isdigit()):
        raise argparse.ArgumentTypeError(f"must be a whole number >= 0, got {text!r}")
    return int(text)


@dataclass(frozen=True)
class AssignmentSeed:
    """The seed a command grades under, and where it came from."""

    seed: int
    file: Path | None  # None: given as --seed N
    made: bool = False  # made now, by this command

    @property
    def fingerprint(self) -> str:
        return fingerprint(self.seed)

    def line(self) -> str:
        """The line each command prints on stderr: the fingerprint and the file."""
        where = "--seed" if self.file is None else shown(self.file)
        made = ", made now, mode 600" if self.made else ""
        if self.made and self.file.name == FILE_NAME:
            made += ": the commands run in this folder or below use it"
        return f"raykit_grading: assignment seed {self.fingerprint} ({where}{made})"


def shown(path: Path) -> str:
    """``path`` as a line shows it: from the current folder if it is inside it."""
    path = Path(path).absolute()
    try:
        return f"./{path.relative_to(Path.cwd())}"
    except ValueError:
        return str(path)


def find_assignment(start: Path | None = None) -> Path | None:
    """The assignment folder: the first of ``start`` (default: the current folder) and its
    parents that holds ``grading-seed``. The search does not go up into your home folder or
    the filesystem's root, nor onto another filesystem (past a mount point), so a seed made
    elsewhere for something else is never picked up."""
    folder = Path(start or Path.cwd()).absolute()
    try:
        home = Path.home().absolute()
    except RuntimeError:  # no home folder known
        home = None
    device = folder.stat().st_dev
    while True:
        if os.path.lexists(folder / FILE_NAME):
            return folder
        parent = folder.parent
        if parent == folder or parent == home or parent.parent == parent:
            return None
        try:
            if parent.stat().st_dev != device:
                return None
        except OSError:
            return None
        folder = parent


def assignment_seed(
    assignment: Path | None = None,
    *,
    make: bool,
    seed: int | None = None,
    seed_file: Path | None = None,
) -> AssignmentSeed:
    """The assignment's seed, as every command finds it: ``seed`` (``--seed N``), else the
    seed in ``seed_file`` (made if missing), else ``assignment/grading-seed``, else the one
    :func:`find_assignment` finds from the current folder. Where there is none, ``make``
    makes it (in ``assignment``, else the current folder); else :class:`SeedFileError` says
    where it looked. Raises :class:`SeedFileError` for a file that cannot be read or made."""
    if seed is not None:
        return AssignmentSeed(seed, None)
    if seed_file is not None:
        return AssignmentSeed(*_read_or_make(Path(seed_file), make=True))
    if assignment is not None:
        assignment = Path(assignment)
        if not assignment.is_dir():
            raise SeedFileError(f"{assignment}: no such assignment folder")
        return AssignmentSeed(*_read_or_make(assignment / FILE_NAME, make=make))
    found = find_assignment()
    if found is not None:
        return AssignmentSeed(*_read_or_make(found / FILE_NAME, make=False))
    if not make:
        raise SeedFileError(
            f"no {FILE_NAME} in {Path.cwd()} or the folders above it: run the command in the "
            "assignment folder, or give --assignment DIR"
        )
    return AssignmentSeed(*_read_or_make(Path.cwd() / FILE_NAME, make=True))


def _read_or_make(path: Path, *, make: bool) -> tuple[int, Path, bool]:
    if make:
        seed, made = seed_from_file(path)
        return seed, path, made
    if not os.path.lexists(path):
        raise SeedFileError(f"{path}: no such seed file")
    return read_seed_file(path), path, False

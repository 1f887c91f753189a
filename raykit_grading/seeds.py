"""One secret seed per assignment: every student, and every regrade, gets the same graded inputs.

The graded inputs (:meth:`raykit_grading.catalog.GradingTest.graded_inputs`) are drawn from a
seed. The seed is made once, when an assignment's grading is set up, and kept in a *seed file*
that only the instructor (and the grader, as root) can read:

* ``gradescope -o autograder.zip``: the zip carries it as ``grading-seed`` at its top, which
  ``setup.sh`` closes to root with the rest of ``/autograder/source``; the builder keeps a copy
  beside the zip (``autograder.grading-seed``), so a rebuilt zip grades with the same inputs.
* ``batch SUBMISSIONS -o OUT``: ``OUT/grading-seed``, so a batch that is run again (new students,
  ``--regrade``) grades with the same inputs.
* ``grade SUBMISSION -o results.json``: ``grading-seed`` beside results.json.

Each takes ``--seed-file PATH`` instead (made if missing), and ``grade``/``batch`` take
``--seed N`` to repeat one draw. A seed file is made with mode 600, atomically (two graders
starting at once read the same seed). results.json names the seed by its :func:`fingerprint`
only: hidden results are shown to students after the due date, and a student who knew the
seed could draw the hidden tests' inputs for a regrade.
"""

from __future__ import annotations

import hashlib
import os
import secrets
import stat
import sys
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
    words = [w for line in text.splitlines() if not line.lstrip().startswith("#")
             for w in line.split()]  # fmt: skip
    if len(words) != 1 or not (words[0].isascii() and words[0].isdigit()):
        raise SeedFileError(f"{path}: not a grading seed (expected one whole number >= 0)")
    if info.st_mode & 0o077:
        _close_to_others(path, info)
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

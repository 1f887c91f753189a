"""A grading run's options as a command line gives them: ``grade``'s and ``batch``'s, and the
platforms' entrypoints', which take the same (``RAYKIT_GRADE_OPTIONS``, for testing them).

    --seed N  --child-python PYTHON  --only TEST...  --wall-seconds S  --total-seconds S
"""

from __future__ import annotations

import argparse

from raykit_grading.assignment.catalog import by_name
from raykit_grading.assignment.seeds import seed_argument
from raykit_grading.grading.grade import TOTAL_SECONDS, Options
from raykit_grading.sandbox.base import Limits


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number of seconds, got {text!r}") from None
    if not 0 < value <= 86400:
        raise argparse.ArgumentTypeError(f"must be between 0 and 86400, got {value:g}")
    return value


def add_grading_arguments(parser: argparse.ArgumentParser, total_seconds: float) -> None:
    """The options every way of grading takes; ``total_seconds`` its default total time."""
    parser.add_argument(
        "--seed",
        type=seed_argument,
        help="draw the graded inputs from this seed instead (a whole number; overrides "
        "--seed-file)",
    )
    parser.add_argument(
        "--child-python",
        help="Python to run submissions with (default: this one; needs numpy and Pillow)",
    )
    parser.add_argument(
        "--only",
        nargs="+",
        metavar="TEST",
        help="grade only these tests (numbers such as 3.6, or name beginnings)",
    )
    parser.add_argument(
        "--wall-seconds",
        type=_seconds,
        default=20.0,
        help="time one test's code may take before it is stopped (default 20)",
    )
    parser.add_argument(
        "--total-seconds",
        type=_seconds,
        default=total_seconds,
        help=f"time all of one submission's tests may take together (default {total_seconds:g})",
    )


def grading_options(args: argparse.Namespace, parser: argparse.ArgumentParser) -> Options:
    """The :class:`~raykit_grading.grading.grade.Options` that ``args`` give; a ``--only``
    that names no test is the parser's error (exit status 2)."""
    if args.only and not by_name(args.only):
        parser.error(f"--only {' '.join(args.only)}: no test has that number or name")
    limits = Limits(wall_seconds=args.wall_seconds, cpu_seconds=int(args.wall_seconds) + 1)
    return Options(args.child_python, limits, args.total_seconds)


__all__ = ["TOTAL_SECONDS", "add_grading_arguments", "grading_options"]

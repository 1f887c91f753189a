"""``python -m raykit_grading COMMAND``: release, grade, batch, gradescope, tests."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m raykit_grading", description=__doc__)
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    grade = commands.add_parser("grade", help="grade one submission into results.json")
    grade.add_argument("submission", type=Path, help="folder holding the student's raykit/")
    grade.add_argument("-o", "--output", type=Path, required=True, help="results.json to write")
    grade.add_argument("--feedback", type=Path, help="folder for feedback pictures")

    batch = commands.add_parser("batch", help="grade a folder of submissions on all cores")
    batch.add_argument("submissions", type=Path, help="folder with one folder per student")
    batch.add_argument(
        "-o",
        "--output",
        type=Path,
        required=True,
        help="folder for scores.csv and one feedback folder per student",
    )
    batch.add_argument("--jobs", type=int, default=None, help="parallel graders (all cores)")

    release = commands.add_parser("release", help="build the student release")
    release.add_argument("-o", "--output", type=Path, required=True, help="folder to create")

    zip_ = commands.add_parser("gradescope", help="build the Gradescope autograder zip")
    zip_.add_argument("-o", "--output", type=Path, required=True, help="autograder.zip")

    commands.add_parser("tests", help="list the grading tests, their points and visibility")

    for sub in (grade, batch):
        sub.add_argument(
            "--child-python",
            help="Python to run submissions with (as root: one the sandbox user may run)",
        )
        sub.add_argument(
            "--only",
            nargs="*",
            metavar="NAME",
            help="grade only the tests whose names start with these",
        )
        sub.add_argument(
            "--wall-seconds",
            type=float,
            default=20.0,
            help="time one test's code may take before it is stopped (default 20)",
        )
    args = parser.parse_args(argv)
    if args.command in ("grade", "batch"):
        from raykit_grading.sandbox import Limits

        limits = Limits(wall_seconds=args.wall_seconds, cpu_seconds=int(args.wall_seconds) + 1)
        shared = {"child_python": args.child_python, "names": args.only, "limits": limits}

    if args.command == "grade":
        from raykit_grading.grade import grade_to_file

        results = grade_to_file(
            args.submission,
            args.output,
            feedback=args.feedback,
            **shared,
        )
        total = sum(t["max_score"] for t in results["tests"])
        print(f"wrote {args.output}: {results['score']:g} of {total:g} points")
    elif args.command == "batch":
        from raykit_grading.batch import grade_folder

        grade_folder(
            args.submissions,
            args.output,
            jobs=args.jobs,
            **shared,
        )
    elif args.command == "release":
        from raykit_grading.release import build_release

        build_release(args.output)
    elif args.command == "gradescope":
        from raykit_grading.gradescope import build_zip

        build_zip(args.output)
    elif args.command == "tests":
        from raykit_grading.catalog import TESTS

        for test in TESTS:
            print(f"{test.points:>4g}  {test.visibility:<15} {test.name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

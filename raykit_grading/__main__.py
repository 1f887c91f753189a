"""``python -m raykit_grading COMMAND``: release, grade, batch, gradescope, prairielearn, tests,
try-zip.

The commands share the assignment's secret seed, ``grading-seed`` in the assignment folder:
the current folder or the first of its parents that holds one (or ``--assignment DIR``); where
there is none, release, gradescope, grade and batch make it in the current folder. Each prints
the seed's fingerprint and its file in one line on stderr.

Exit status: 0 done (grade: graded, whatever the score); 1 batch: some student could not be
graded; 2 bad arguments; 3 the grader could not grade (no sandbox here, or it
failed on some tests): it says so, and never stands a made-up score in for a grade.
"""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path

from raykit_grading.assignment.seeds import SeedFileError, assignment_seed
from raykit_grading.grading.options import TOTAL_SECONDS, add_grading_arguments, grading_options


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m raykit_grading", description=__doc__, allow_abbrev=False
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    def command(name: str, **kw) -> argparse.ArgumentParser:
        return commands.add_parser(name, allow_abbrev=False, **kw)

    grade = command("grade", help="grade one submission into results.json")
    grade.add_argument(
        "submission", type=Path, help="the student's folder holding raykit/, or their zip"
    )
    grade.add_argument("-o", "--output", type=Path, required=True, help="results.json to write")
    grade.add_argument("--feedback", type=Path, help="folder for feedback pictures")

    batch = command("batch", help="grade a folder of submissions, a few at a time")
    batch.add_argument(
        "submissions",
        type=Path,
        help="folder of student folders and/or zips, or Gradescope's export (zip or folder)",
    )
    batch.add_argument(
        "-o",
        "--output",
        type=Path,
        required=True,
        help="folder for scores.csv and one feedback folder per student",
    )
    batch.add_argument("--jobs", type=int, default=None, help="students graded at once")
    batch.add_argument(
        "--regrade", action="store_true", help="grade everyone again, not only the new ones"
    )

    release = command("release", help="build the student release")
    release.add_argument("-o", "--output", type=Path, required=True, help="folder to create")

    zip_ = command("gradescope", help="build the Gradescope autograder zip")
    zip_.add_argument("-o", "--output", type=Path, required=True, help="autograder.zip")
    zip_.add_argument(
        "--seed-file",
        type=Path,
        help="the assignment's secret seed from this file instead, made (mode 600) if missing",
    )

    learn = command(
        "prairielearn", help="write the PrairieLearn grader image's build folder and question"
    )
    learn.add_argument("-o", "--output", type=Path, required=True, help="folder to write")
    learn.add_argument(
        "--image",
        help="the image's name on Docker Hub, for info.json (e.g. yourname/raykit-grader)",
    )
    learn.add_argument(
        "--base-image",
        default="ubuntu:22.04",
        help="the grader image's base (default ubuntu:22.04, from Docker Hub; where it cannot be "
        "reached: python -m raykit_grading.platforms.containers base-image makes "
        "raykit/debian-bookworm-base:latest)",
    )
    learn.add_argument(
        "--seed-file",
        type=Path,
        help="the assignment's secret seed from this file instead, made (mode 600) if missing",
    )

    command("tests", help="list the grading tests by stage: points, visibility, totals")

    try_zip = command(
        "try-zip", help="build the zip's image and grade submissions in Docker, as Gradescope will"
    )
    try_zip.add_argument("zip", type=Path, help="autograder.zip")
    try_zip.add_argument(
        "submissions",
        type=Path,
        nargs="+",
        metavar="SUBMISSION",
        help="a folder (its contents go to /autograder/submission, as on Gradescope) or a zip",
    )
    try_zip.add_argument(
        "--base-image",
        default="gradescope/autograder-base:ubuntu-22.04",
        help="image to build on (default: Gradescope's, gradescope/autograder-base:ubuntu-22.04)",
    )
    try_zip.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("try-zip"),
        help="folder for the results (try-zip/)",
    )

    for sub in (release, zip_, learn, grade, batch, try_zip):
        sub.add_argument(
            "--assignment",
            type=Path,
            metavar="DIR",
            help="the assignment folder, which holds its secret seed grading-seed (default: the "
            "current folder or the first of its parents that holds one; "
            + (
                "try-zip warns if the zip's seed is not its seed)"
                if sub is try_zip
                else "if none does, the seed is made in the current folder)"
            ),
        )
    for sub in (grade, batch):
        sub.add_argument(
            "--seed-file",
            type=Path,
            help="the assignment's secret seed from this file instead, made (mode 600) if missing",
        )
        add_grading_arguments(sub, TOTAL_SECONDS)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command in ("grade", "batch"):
        options = grading_options(args, parser)

    if args.command == "grade":
        return _grade(args, options)
    if args.command == "batch":
        from raykit_grading.grading.batch import grade_folder

        return grade_folder(
            args.submissions,
            args.output,
            jobs=args.jobs,
            names=args.only,
            options=options,
            regrade=args.regrade,
            seed=args.seed,
            seed_file=args.seed_file,
            assignment=args.assignment,
        )
    if args.command == "try-zip":
        from raykit_grading.platforms.containers import try_zip

        return try_zip(
            args.zip, args.submissions, args.base_image, args.output, assignment=args.assignment
        )
    if args.command == "release":
        from raykit_grading.assignment.release import build_release

        if args.output.exists():
            parser.error(f"{args.output} exists; give a new folder")
        found = _assignment_seed(args.assignment)
        if found is None:
            return 2
        from raykit_grading.assignment.catalog import TESTS, VISIBLE

        visible = [t for t in TESTS if t.visibility == VISIBLE]
        bar = _progress(len(visible), "the practice tests' references")
        done = []

        def made(test) -> None:  # a bar on a terminal, else a line a test
            done.append(test)
            if bar:
                bar.update()
            else:
                print(f"release: {len(done)} of {len(visible)}: {test.name}", file=sys.stderr)

        try:
            build_release(args.output, made)
        finally:
            if bar:
                bar.close()
        print(found.line(), file=sys.stderr)
    elif args.command == "gradescope":
        from raykit_grading.platforms.gradescope import build_zip

        found = _assignment_seed(args.assignment, seed_file=args.seed_file)
        if found is None:
            return 2
        build_zip(args.output, found.seed)
        print(found.line(), file=sys.stderr)
    elif args.command == "prairielearn":
        from raykit_grading.platforms.prairielearn import DEFAULT_IMAGE, write_course_files

        found = _assignment_seed(args.assignment, seed_file=args.seed_file)
        if found is None:
            return 2
        try:
            write_course_files(
                args.output, args.image or DEFAULT_IMAGE, found.seed, args.base_image
            )
        except OSError as exc:
            print(f"raykit_grading: error: {args.output}: {exc.strerror}", file=sys.stderr)
            return 2
        print(found.line(), file=sys.stderr)
    elif args.command == "tests":
        from raykit_grading.assignment.catalog import listing

        print(listing())
    return 0


def _grade(args, options) -> int:
    from raykit_grading.assignment.catalog import by_name
    from raykit_grading.grading.grade import grade_to_file

    if not (args.submission.is_dir() or args.submission.suffix.lower() == ".zip"):
        what = "not a folder or a zip" if args.submission.exists() else "no such folder or zip"
        print(f"raykit_grading: error: {args.submission}: {what}", file=sys.stderr)
        return 2
    if not args.submission.is_dir():  # a zip: graded as a folder holding it, as batch does
        if not args.submission.is_file():
            print(f"raykit_grading: error: {args.submission}: no such zip", file=sys.stderr)
            return 2
        import tempfile

        with tempfile.TemporaryDirectory(prefix="raykit-zip-") as folder:
            holding = Path(folder) / args.submission.stem
            holding.mkdir()
            shutil.copyfile(args.submission, holding / args.submission.name)
            args.submission = holding
            return _grade(args, options)
    found = _assignment_seed(args.assignment, seed=args.seed, seed_file=args.seed_file)
    if found is None:
        return 2
    tests = by_name(args.only)
    bar = _progress(len(tests), f"grading {args.submission.name}")
    try:
        status = grade_to_file(
            args.submission,
            args.output,
            names=args.only,
            feedback=args.feedback,
            seed=found.seed,
            options=options,
            progress=(lambda test: bar.update()) if bar else None,
        )
    finally:
        if bar:
            bar.close()
    import json

    results = json.loads(args.output.read_text())
    total = sum(t["max_score"] for t in results["tests"])
    if found.made and status == 3:  # nothing was graded under it: leave no seed behind either
        found.file.unlink(missing_ok=True)
    elif status != 3:
        print(found.line(), file=sys.stderr)
    if status == 3:
        print(f"wrote {args.output}: NOT GRADED (see above)")
    else:
        print(f"wrote {args.output}: {results['score']:g} of {total:g} points")
    broken = results.get("extra_data", {}).get("does_not_import")
    if status == 0 and broken:
        print(f"raykit_grading: note: {args.submission}: raykit does not import, so no test "
              f"ran: {broken.splitlines()[0]}", file=sys.stderr)  # fmt: skip
    if status == 0 and any("no raykit package" in t["output"] for t in results["tests"]):
        why = results["tests"][0]["output"].splitlines()[0]  # what was found, what expected
        print(f"raykit_grading: note: {args.submission}: {why}: graded 0", file=sys.stderr)
    return status


def _assignment_seed(assignment: Path | None, **given):
    """The command's :class:`~raykit_grading.assignment.seeds.AssignmentSeed` (found, or made), or
    None after saying why in one line."""
    try:
        return assignment_seed(assignment, make=True, **given)
    except SeedFileError as exc:
        print(f"raykit_grading: error: {exc}", file=sys.stderr)
        return None


def _progress(total: int, what: str):
    """A progress bar on stderr when it is a terminal and tqdm is installed."""
    if not sys.stderr.isatty():
        return None
    try:
        from tqdm import tqdm
    except ImportError:
        return None
    return tqdm(total=total, desc=what, unit="test", file=sys.stderr, leave=False)


if __name__ == "__main__":
    sys.exit(main())

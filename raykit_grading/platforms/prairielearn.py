"""PrairieLearn: the grader image's build folder, the question, and PrairieLearn's results.json.

    python -m raykit_grading prairielearn -o DIR [--image NAME] [--base-image IMAGE]
        [--assignment DIR]

writes what a course needs (``DIR/README.md`` says the steps):

* ``DIR/grader-image/``: a ``Dockerfile`` (its base the ``BASE_IMAGE`` build argument, default
  :data:`DEFAULT_BASE`, or ``--base-image``: where Docker Hub cannot be reached, the Debian
  base image ``python -m raykit_grading.platforms.containers base-image`` makes, as for ``try-zip``)
  and ``source/``, the same pieces as Gradescope's zip (:mod:`raykit_grading.platforms.gradescope`:
  ``setup.sh``, the pinned requirements, the grader, the reference raykit, the scenes) and
  the entrypoint ``run_prairielearn``. PrairieLearn pulls images from Docker Hub, so the
  image may be public: it holds **neither the seed nor the hidden scenes**. ``setup.sh``
  runs at build time, as on Gradescope: a Python with what ``grader-requirements.txt`` pins,
  bubblewrap, and the chroot sandbox's tree.
* ``DIR/questions/raykit/``: ``info.json`` (external grading with that image and entrypoint,
  no network, a :data:`TIMEOUT` s timeout), ``question.html`` (a ``pl-file-upload`` of
  :data:`SUBMITTED_FILE`, the student's ``raykit/`` folder zipped, and the grader's results)
  and ``tests/``: the assignment's secret seed and the hidden scenes. A course's repository is
  not readable by students; PrairieLearn mounts ``tests/`` at ``/grade/tests`` for each job.

PrairieLearn runs the entrypoint as root in a fresh container per submission: Docker's default
confinement (no namespaces, so the chroot sandbox of :mod:`raykit_grading.sandbox.confine`), no
network, ``/grade`` laid out as its external-grading docs say. :func:`run_job` grades
``/grade/student`` with the seed and hidden scenes of ``/grade/tests`` and writes
``/grade/results/results.json`` in PrairieLearn's format (:func:`to_prairielearn`):

* a submission in the wrong shape (nothing or something else uploaded, no ``raykit/``
  package in the zip, a zip too large or not a zip; a ``raykit/`` folder, as a workspace
  question's ``gradedFiles`` sends it, is taken as well) is ``gradable: false`` with
  ``format_errors``: PrairieLearn then counts no attempt;
* a grader that cannot grade (no seed in ``tests/``, no sandbox, a test the grader failed on,
  past the time limit) is ``gradable: false`` with a message beginning ``NOT GRADED``, never a
  score;
* hidden tests count in the score but show as one line, their points together and nothing
  else (a hidden test's name, message or picture never reaches the student). PrairieLearn has
  no "after the due date" and shows the score at once: the points the hidden tests earned
  together are what a student learns (docs/instructors.md says what an instructor can do);
* a visible render's picture is a base64 PNG in the test's ``images``; pictures are left out,
  largest first, while the file would pass PrairieLearn's 1 MB, and ``message`` says so.

The entrypoint exits 0 whenever results.json is written: PrairieLearn throws away the results
of a container that exits non-zero.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
import uuid
from pathlib import Path

from raykit_grading.assignment.catalog import HIDDEN_SCENES, REPO, VISIBLE
from raykit_grading.assignment.seeds import (
    HEADER,
    SeedFileError,
    fingerprint,
    new_seed,
    read_seed_file,
)
from raykit_grading.grading.grade import grade_to_file
from raykit_grading.grading.options import add_grading_arguments, grading_options
from raykit_grading.grading.results import split_html_output, write_results
from raykit_grading.platforms.gradescope import HIDDEN_FOLDER, grader_files, setup_script

SUBMITTED_FILE = "raykit.zip"
TAKEN = {SUBMITTED_FILE, "raykit"}  # the upload, or the folder a workspace question grades
DEFAULT_BASE = "ubuntu:22.04"  # what Gradescope's base image is built on
LOCAL_BASE = "raykit/debian-bookworm-base:latest"  # containers.DEBIAN_BASE: no registry needed
DEFAULT_IMAGE = "your-docker-hub-name/raykit-grader:latest"  # a placeholder: --image NAME
SOURCE = "/grader/source"  # in the image: the grader, root's alone
ENTRYPOINT = "/grader/run_prairielearn"
# PrairieLearn's limit is 600 s; the grader stops itself well before it, so that
# results.json (NOT GRADED, if need be) is written before PrairieLearn kills the container:
# the student's code may take TOTAL_SECONDS together, everything at most STOP_SECONDS
TIMEOUT = 600
STOP_SECONDS = 540
TOTAL_SECONDS = 360.0
RESULTS_BUDGET = 1_000_000  # bytes, under PrairieLearn's 1 MiB
SEED_NAME = "grading-seed"
HIDDEN_NAME = "hidden-scenes"
HIDDEN_TESTS = "Hidden tests"

DOCKERFILE = f"""\
# The raykit grader for PrairieLearn. Build with the base image as a build argument
# (default: {{base}}), push to Docker Hub, and name it in the question's info.json. It holds
# no secret: the seed and hidden scenes come with each grading job.
ARG BASE_IMAGE={{base}}
FROM ${{{{BASE_IMAGE}}}}
COPY source {SOURCE}
RUN cp {SOURCE}/run_prairielearn {ENTRYPOINT} \\
 && chmod 755 {ENTRYPOINT} \\
 && cd {SOURCE} && bash {SOURCE}/setup.sh
ENTRYPOINT ["{ENTRYPOINT}"]
"""

RUN = f"""#!/usr/bin/env bash
# PrairieLearn runs this, as root, in a fresh container for every submission, with the job's
# files in /grade: student/ (the upload), tests/ (the question's: seed, hidden scenes).
set -uo pipefail
grade="${{RAYKIT_GRADE_ROOT:-/grade}}"
source="${{RAYKIT_GRADER_SOURCE:-{SOURCE}}}"
grader_python="${{RAYKIT_GRADER_PYTHON:-/opt/raykit-grader/bin/python}}"
results="$grade/results/results.json"
mkdir -p "$grade/results"
rm -f "$results"
# stopped at {STOP_SECONDS} s, inside the question's {TIMEOUT} s: results.json is written first
# RAYKIT_GRADE_OPTIONS (e.g. "--only 3.6 --wall-seconds 5") is for testing this script
# shellcheck disable=SC2086
(cd "$source" && PYTHONPATH="$source" timeout --kill-after=10 {STOP_SECONDS} \\
  "$grader_python" -m raykit_grading.platforms.prairielearn job "$grade" \\
  ${{RAYKIT_GRADE_OPTIONS:-}})
status=$?
if [ ! -s "$results" ]; then  # the grader did not finish: say so, never a silent zero
  why="the grader could not run (exit status $status)"
  if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
    why="grading took longer than {STOP_SECONDS} s"
  fi
  echo "raykit_grading: error: $why" >&2
  printf '{{"gradable": false, "score": 0, "message": "NOT GRADED: %s; ask your instructor"}}\\n' \\
    "$why" > "$results"
fi
exit 0  # PrairieLearn keeps results.json only from a container that exits 0
"""

QUESTION_HTML = f"""\
<pl-question-panel>
  <p>
    Upload your work as <code>{SUBMITTED_FILE}</code>: a zip of your <code>raykit/</code>
    folder (the folder itself, with its <code>__init__.py</code>, at the zip's top). It is
    graded on inputs drawn for this assignment, plus hidden tests, which count in your score
    and are shown as one line.
  </p>
  <pl-file-upload file-names="{SUBMITTED_FILE}"></pl-file-upload>
</pl-question-panel>

<pl-submission-panel>
  <pl-external-grader-results></pl-external-grader-results>
</pl-submission-panel>
"""


def info_json(image: str, question_uuid: str) -> dict:
    """The question's info.json: external grading with the grader image."""
    return {
        "uuid": question_uuid,
        "title": "raykit: the ray tracer",
        "topic": "Ray tracing",
        "tags": ["raykit", "autograder"],
        "type": "v3",
        "singleVariant": True,
        "gradingMethod": "External",
        "externalGradingOptions": {
            "enabled": True,
            "image": image,
            "entrypoint": ENTRYPOINT,
            "timeout": TIMEOUT,
            "enableNetworking": False,
        },
    }


README = """\
# raykit's grader on PrairieLearn

Written by `python -m raykit_grading prairielearn -o {out}` (grading seed {fingerprint}).

1. Build the grader image and push it to Docker Hub (PrairieLearn pulls it from there; it holds
   no secret, so it may be public):

   ```bash
   docker build -t {image} {out}/grader-image
   docker push {image}
   ```

   The base is {base}; another is given with `--build-arg BASE_IMAGE=...` (one with
   apt-get and Python 3.10 or newer). Where Docker Hub cannot be reached (the build then
   fails pulling the base), make a Debian base image from the distribution's packages once
   (as root, with `debootstrap` installed) and build on it:

   ```bash
   python -m raykit_grading.platforms.containers base-image      # {local_base}
   docker build --build-arg BASE_IMAGE={local_base} -t {image} {out}/grader-image
   ```

   (or write this folder again with `--base-image {local_base}`, which makes it the default).
2. Copy the question into your course: `cp -r {out}/questions/raykit
   COURSE/questions/raykit`, commit and sync. Its `tests/` folder holds the assignment's
   secret seed and the hidden scenes: your course repository must stay private.
3. Keep `externalGradingOptions.timeout` in `info.json` at {timeout} s (PrairieLearn's
   largest): the grader stops itself at {stop} s and says so.
4. Add the question to an assessment. Students upload `{submitted}`, their `raykit/` folder
   zipped.

The seed is the assignment's (`grading-seed` in the assignment folder, see the instructor
guide): `gradescope`, `grade` and `batch` run in that folder grade with the same inputs, and
writing this folder again there keeps the question's inputs.
"""


def write_course_files(
    out: Path, image: str = DEFAULT_IMAGE, seed: int | None = None, base: str = DEFAULT_BASE
) -> Path:
    """Write ``out``: the grader image's build folder (on the base image ``base`` unless the
    build says another), the question and the README, the question grading under ``seed``:
    the assignment's (the command passes :func:`raykit_grading.assignment.seeds.assignment_seed`'s);
    None draws one that only this question holds."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    seed = new_seed() if seed is None else seed
    build = out / "grader-image"
    question = out / "questions" / "raykit"
    old_info = question / "info.json"
    question_uuid = (
        json.loads(old_info.read_text()).get("uuid") if old_info.is_file() else None
    ) or str(uuid.uuid4())  # kept when written again: PrairieLearn knows the question by it
    for folder in (build, question):
        shutil.rmtree(folder, ignore_errors=True)
    source = build / "source"
    for name, path in grader_files():
        target = source / name
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, target)
    for name, text in (("setup.sh", setup_script()), ("run_prairielearn", RUN)):
        (source / name).write_text(text)
        (source / name).chmod(0o755)
    (build / "Dockerfile").write_text(DOCKERFILE.format(base=base))
    (build / ".dockerignore").write_text("**/__pycache__\n")
    tests = question / "tests"
    shutil.copytree(REPO / HIDDEN_FOLDER, tests / HIDDEN_NAME)
    (tests / SEED_NAME).write_text(f"{HEADER}{seed}\n")
    (tests / SEED_NAME).chmod(0o600)
    (question / "info.json").write_text(json.dumps(info_json(image, question_uuid), indent=2))
    (question / "question.html").write_text(QUESTION_HTML)
    (out / "README.md").write_text(
        README.format(
            out=out, image=image, fingerprint=fingerprint(seed), timeout=TIMEOUT,
            stop=STOP_SECONDS, submitted=SUBMITTED_FILE, base=base, local_base=LOCAL_BASE,
        )
    )  # fmt: skip
    print(f"wrote {out}: the grader image's build folder, the question and README.md")
    if image == DEFAULT_IMAGE:
        print(f"raykit_grading: note: info.json names the image {image}: write it again with "
              "--image NAME/raykit-grader (your Docker Hub name)", file=sys.stderr)  # fmt: skip
    return out


# ---- results ---------------------------------------------------------------------------------


def not_gradable(message: str, format_errors: list[str] | None = None) -> dict:
    """PrairieLearn's results for a submission it is not to count: ``format_errors`` when the
    submission is at fault, a NOT GRADED message when the grader is."""
    results: dict = {"gradable": False, "score": 0, "message": message}
    if format_errors:
        results["format_errors"] = format_errors
    return results


def to_prairielearn(graded: dict, status: int = 0) -> dict:
    """The grader's results (Gradescope's format, :mod:`raykit_grading.grading.results`) in
    PrairieLearn's: see the module's docstring. ``status``: the ``grade`` command's."""
    if status != 0:
        return not_gradable(
            "NOT GRADED: the autograder could not grade this submission; ask your instructor\n"
            + graded.get("output", "")
        )
    entries = graded.get("tests", [])
    if graded.get("extra_data", {}).get("sandbox", "").startswith("none"):  # nothing ran
        why = entries[0]["output"].splitlines()[0] if entries else "no raykit package"
        return not_gradable(graded.get("output", ""), [why])
    total = sum(e["max_score"] for e in entries)
    tests, hidden = [], []
    for entry in entries:
        if entry.get("visibility") != VISIBLE:
            hidden.append(entry)
            continue
        text, picture = split_html_output(entry["output"])
        test = {
            "name": entry["name"],  # the catalogue's, which begins with its number
            "points": entry["score"],
            "max_points": entry["max_score"],
            "message": text.splitlines()[0] if text else "",
            "output": text,
        }
        if picture:
            test["images"] = [{"label": "yours | expected | where they differ", "url": picture}]
        tests.append(test)
    if hidden:
        earned = round(sum(e["score"] for e in hidden), 4)
        most = sum(e["max_score"] for e in hidden)
        tests.append({
            "name": HIDDEN_TESTS,
            "description": f"{len(hidden)} tests on inputs that are not shown",
            "points": earned,
            "max_points": most,
            "message": f"hidden tests: {earned:g} of {most:g} points (which ones, and why, "
                       "are not shown)",
            "output": "",
        })  # fmt: skip
    results = {
        "gradable": True,
        "score": round(graded["score"] / total, 6) if total else 0.0,
        "message": graded.get("output", ""),
        "tests": tests,
        # what Gradescope's results say too: no secret (the seed's fingerprint only)
        "extra_data": {
            k: v
            for k, v in graded.get("extra_data", {}).items()
            if k in ("sandbox", "seed_fingerprint")
        },  # fmt: skip
    }
    return within_limit(results)


def within_limit(results: dict, budget: int = RESULTS_BUDGET) -> dict:
    """``results`` with pictures left out, largest first, until it is at most ``budget``
    bytes as JSON; ``message`` says how many were left out."""
    with_pictures = sorted(
        (t for t in results.get("tests", []) if t.get("images")),
        key=lambda t: -len(json.dumps(t["images"])),
    )
    left_out = 0
    while len(json.dumps(results).encode()) > budget and with_pictures:
        del with_pictures.pop(0)["images"]
        left_out += 1
    if left_out:
        results["message"] += (
            f"\n{left_out} feedback picture(s) left out: PrairieLearn's results are at most "
            "1 MB (the text of every test is all there)"
        )
    return results


# ---- the grading job, in PrairieLearn's container ----------------------------------------


def submission_problems(student: Path) -> list[str]:
    """What is wrong with the upload's shape before it is opened (empty if nothing): it is
    :data:`SUBMITTED_FILE` (``pl-file-upload``), or a ``raykit/`` folder (a workspace's
    ``gradedFiles``), and nothing else."""
    if not student.is_dir():
        return [f"nothing was submitted: upload {SUBMITTED_FILE}"]
    names = sorted(os.listdir(student))
    problems = [f"{name}: not a file this question takes (it takes {SUBMITTED_FILE} only)"
                for name in names if name not in TAKEN]  # fmt: skip
    if not TAKEN.intersection(names):
        problems.append(f"no {SUBMITTED_FILE}: upload your raykit/ folder zipped")
    return problems


def prepare_secrets(tests: Path) -> tuple[int | None, str]:
    """The question's seed, its hidden scenes put where the grader reads them: (the seed, "")
    or (None, why not)."""
    try:
        seed = read_seed_file(tests / SEED_NAME)
    except SeedFileError as exc:
        return None, f"the question's tests/ has no usable grading seed ({exc})"
    scenes = tests / HIDDEN_NAME
    if not HIDDEN_SCENES.is_dir():  # in the image (a clone has its own)
        if not scenes.is_dir():
            return None, f"the question's tests/ has no {HIDDEN_NAME}/"
        shutil.copytree(scenes, HIDDEN_SCENES)
    return seed, ""


def job_parser() -> argparse.ArgumentParser:
    """``job GRADE_ROOT`` and the grading options (:mod:`raykit_grading.grading.options`)."""
    parser = argparse.ArgumentParser(prog="python -m raykit_grading.platforms.prairielearn")
    commands = parser.add_subparsers(dest="command", required=True)
    job = commands.add_parser("job", help="grade a PrairieLearn job folder (/grade)")
    job.add_argument("grade_root", type=Path)
    add_grading_arguments(job, TOTAL_SECONDS)
    return parser


def run_job(grade_root: Path, options: list[str]) -> int:
    """Grade ``grade_root/student`` into ``grade_root/results/results.json`` with the grading
    ``options`` (as a command line gives them); the exit status of
    :func:`~raykit_grading.grading.grade.grade_to_file` (results.json is written whatever it
    is)."""
    parser = job_parser()
    return _grade_job(parser.parse_args(["job", str(grade_root), *options]), parser)


def _grade_job(args: argparse.Namespace, parser: argparse.ArgumentParser) -> int:
    grading = grading_options(args, parser)
    results = args.grade_root / "results" / "results.json"
    problems = submission_problems(args.grade_root / "student")
    if problems:
        write_results(not_gradable("The submission is not in the shape asked for.", problems),
                      results)  # fmt: skip
        return 0
    seed, why = prepare_secrets(args.grade_root / "tests")
    if seed is None:
        print(f"raykit_grading: error: {why}", file=sys.stderr)
        write_results(not_gradable(f"NOT GRADED: {why}; ask your instructor"), results)
        return 3
    with tempfile.TemporaryDirectory(prefix="raykit-pl-") as private:
        graded_path = Path(private) / "graded.json"
        status = grade_to_file(
            args.grade_root / "student",
            graded_path,
            names=args.only,
            seed=seed if args.seed is None else args.seed,
            options=grading,
        )
        write_results(to_prairielearn(json.loads(graded_path.read_text()), status), results)
    return status


def main(argv: list[str] | None = None) -> int:
    """``python -m raykit_grading.platforms.prairielearn job GRADE_ROOT [grading options]``:
    what the image's entrypoint runs."""
    parser = job_parser()
    return _grade_job(parser.parse_args(argv), parser)


if __name__ == "__main__":
    sys.exit(main())

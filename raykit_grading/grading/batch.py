"""Grading a class (:mod:`raykit_grading.grading.intake`: folders, zips, Gradescope's export), a few
students at a time, into ``scores.csv`` and a class report.

    python -m raykit_grading batch SUBMISSIONS -o OUT/ [--jobs N] [--regrade]

First a preflight (:func:`raykit_grading.grading.grade.preflight`): if no sandbox can be made here,
nothing is graded and the command says why. Then each student is graded by a grader process of
its own (``python -m raykit_grading grade``), with a time budget: a student whose grading
hangs, crashes or cannot be done is that student's "could not grade" line, never the class's.
Submitted code runs only inside sandboxes that see none of OUT/, the other students' folders or
this process; ``scores.csv`` is written by this process alone, one row as each student's
grader has finished (and all its sandboxes are gone), so a batch that is stopped keeps what it
has graded, and running it again grades only the students not graded yet.

Every student is graded on the same inputs, drawn from the assignment's secret seed
(:mod:`raykit_grading.assignment.seeds`: ``grading-seed`` in the assignment folder, found from the
current folder or ``--assignment``, made there if there is none; or ``--seed-file``/``--seed``), the
seed ``gradescope`` puts in the zip. An OUT/ graded before under another seed (its students'
results.json name the fingerprint) is refused, naming both, unless ``--regrade``: one
scores.csv never mixes two seeds' grades.

``OUT/scores.csv``: student, status, score, max_score, then one column per test; the status is
``graded``, ``does not import`` (0 points: the submission's raykit does not import, so no test
ran), ``could not grade: why``, ``not graded: why`` (a submission that could not be taken in)
or ``not a submission: why`` (a stray file beside the submissions). Every entry of the class
is a row. ``OUT/feedback/<student>/``: results.json, the visible tests'
feedback pictures and the student's page (``index.html``), which may be handed to the student;
``OUT/hidden/<student>/``: the hidden tests' pictures, for the instructor only;
``OUT/logs/<student>.log``: what the student's grader said (its sandbox, its own peak memory
and the container's OOM kills, what it could not remove), for the instructor too;
``OUT/report.html``: the class report
(:mod:`raykit_grading.grading.report`). The exit status says whether every submission was graded: 1
(and they are listed) if some submission could not be, 0 otherwise, a stray file beside them
or a run that had no one left to grade included.

Students are graded ``--jobs`` at a time (2 by default), but one at a time in a container with
a memory limit (:func:`jobs_within`): each grader shares the container's memory out as its own
(:mod:`raykit_grading.sandbox.budgets`, L = G + K + M), so two at once could pass the container's
limit together while each is within its own, and one student's test would be stopped for memory a
classmate held.
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path
from zipfile import is_zipfile

from raykit_grading.assignment.catalog import VISIBLE, by_name
from raykit_grading.assignment.seeds import (
    FILE_NAME,
    AssignmentSeed,
    SeedFileError,
    assignment_seed,
    fingerprint,
    read_seed_file,
)
from raykit_grading.grading.grade import GradingImpossible, Options, preflight
from raykit_grading.grading.intake import Entry, entries
from raykit_grading.grading.report import NOT_A_SUBMISSION, class_summary, write_report
from raykit_grading.sandbox.confine import ContainerLimits, container_limits

NAMES_AS_BYTES = {"encoding": "utf-8", "errors": "surrogateescape"}  # folder names as they are
DOES_NOT_IMPORT = "does not import"  # scores.csv's status (results.json says the error)
HIDDEN_PICTURES = "hidden"  # OUT/hidden/<student>/: the hidden tests' pictures
LOGS = "logs"  # OUT/logs/<student>.log: what each student's grader said
MARGIN_SECONDS = 180.0  # a student's grader may take its tests' total time and this much more
JOBS = 2  # students graded at once where nothing says otherwise


def jobs_within(asked: int | None, limits: ContainerLimits) -> tuple[int, str | None]:
    """How many students to grade at once: ``asked`` (:data:`JOBS` if None), or 1 where the
    grader's cgroup has a memory limit (the module's docstring says why); and, where that
    differs from what was asked, one line saying so."""
    jobs = JOBS if asked is None else asked
    if limits.memory_bytes is None or jobs <= 1:
        return jobs, None
    return 1, (
        f"raykit_grading: one student at a time, not {jobs}: this container's "
        f"{limits.memory_bytes >> 20} MB are each grading's own (raykit_grading/sandbox/budgets.py)"
    )


def _read_scores(path: Path) -> dict[str, dict]:
    if not path.is_file():
        return {}
    with open(path, newline="", **NAMES_AS_BYTES) as stream:
        return {row["student"]: row for row in csv.DictReader(stream)}


def grade_folder(
    submissions: Path,
    out: Path,
    *,
    jobs: int | None = None,
    names: list[str] | None = None,
    options: Options | None = None,
    regrade: bool = False,
    seed: int | None = None,
    seed_file: Path | None = None,
    assignment: Path | None = None,
) -> int:
    """Grade every submission in ``submissions`` (a folder or a zip); returns the exit
    status. The seed: ``seed``, else ``seed_file``, else the assignment's
    (:func:`raykit_grading.assignment.seeds.assignment_seed`)."""
    options = options or Options()
    submissions = Path(submissions)
    if not submissions.is_dir() and not (submissions.is_file() and is_zipfile(submissions)):
        print(f"raykit_grading: error: {submissions}: no such folder or zip", file=sys.stderr)
        return 2
    with tempfile.TemporaryDirectory(prefix="raykit-batch-") as scratch:
        students = entries(submissions, Path(scratch))
        if not students:
            print(f"raykit_grading: error: {submissions}: no submissions in it", file=sys.stderr)
            return 2
        given = {"seed": seed, "seed_file": seed_file}
        return _grade_all(students, Path(out), jobs, names, options, regrade, assignment, given)


def _grade_all(students: list[Entry], out, jobs, names, options, regrade, assignment, given):
    try:
        preflight(options)
    except GradingImpossible as exc:
        print(f"raykit_grading: error: cannot grade: {exc}", file=sys.stderr)
        return 3
    try:
        found = assignment_seed(assignment, make=True, **given)
    except SeedFileError as exc:
        print(f"raykit_grading: error: {exc}", file=sys.stderr)
        return 2
    print(found.line(), file=sys.stderr)
    out = Path(out)
    path = out / "scores.csv"
    rows = {} if regrade else _read_scores(path)
    other = _other_seed(out, rows, found)
    if other:
        print(f"raykit_grading: error: {other}", file=sys.stderr)
        return 2
    out.mkdir(parents=True, exist_ok=True)
    if found.file is None:
        draw = ["--seed", str(found.seed)]
    else:
        draw = ["--seed-file", str(found.file.absolute())]
    tests = by_name(names)
    header = ["student", "status", "score", "max_score", *(t.key for t in tests)]
    done = {
        name
        for name, row in rows.items()
        if row.get("status") in ("graded", DOES_NOT_IMPORT)
        and _graded_under(out, name) == found.fingerprint
    }
    todo = [s for s in students if s.name not in done and s.folder is not None]
    if rows and list(next(iter(rows.values())).keys()) != header:
        rows, todo = {}, [s for s in students if s.folder is not None]  # other tests: start over
    for entry in students:  # what is not graded says why, in every run
        if entry.folder is None:
            kind = "not graded" if entry.submission else NOT_A_SUBMISSION
            rows[entry.name] = {"student": entry.name, "status": f"{kind}: {entry.why}"}
    _write_all(path, header, rows)
    jobs, why = jobs_within(jobs, container_limits())
    if why and todo:
        print(why, file=sys.stderr)
    with (
        open(path, "a", newline="", **NAMES_AS_BYTES) as stream,
        ThreadPoolExecutor(jobs) as pool,
    ):
        writer = csv.writer(stream)
        futures = {
            pool.submit(_grade_student, s.folder, s.name, out, names, options, draw): s
            for s in todo
        }
        for future in _progress(as_completed(futures), len(futures)):
            student = futures[future]
            try:
                row = future.result()
            except Exception as exc:  # noqa: BLE001 - one student's trouble stays theirs
                row = {"student": student.name, "status": f"could not grade: {exc!r}"[:300]}
            rows[student.name] = row
            writer.writerow([row.get(k, "") for k in header])
            stream.flush()
    _write_all(path, header, rows)  # sorted, whole
    failed = [
        f"{name}: {row['status']}"
        for name, row in rows.items()
        if row["status"].startswith(("could not grade", "not graded"))
    ]
    strays = [f"{name}: {row['status']}" for name, row in rows.items()
              if row["status"].startswith(NOT_A_SUBMISSION)]  # fmt: skip
    print(f"wrote {path}: {class_summary(rows)}")  # in the class report's words
    report = write_report(out, tests, rows)
    print(f"wrote {report}: the class report (and each student's feedback/<student>/index.html)")
    if strays:
        print("left out, not submissions:\n  " + "\n  ".join(strays), file=sys.stderr)
    if failed:
        print("not graded:\n  " + "\n  ".join(failed), file=sys.stderr)
        return 1
    return 0


def _other_seed(out: Path, rows: dict[str, dict], found: AssignmentSeed) -> str | None:
    """Why ``out`` cannot be graded into under ``found`` (its students were graded under
    another seed), in one line; or None."""
    others = sorted(
        {_graded_under(out, name) for name, row in rows.items() if row.get("status") in
         ("graded", DOES_NOT_IMPORT)} - {found.fingerprint, None}
    )  # fmt: skip
    if not others:
        return None
    old = ""
    try:  # a batch folder from before the assignment seed kept its seed in it
        if fingerprint(read_seed_file(out / FILE_NAME)) in others:
            old = f"; its old seed is {out / FILE_NAME}: --seed-file {out / FILE_NAME} keeps it"
    except SeedFileError:
        pass
    return (
        f"{out} was graded under the seed {', '.join(others)}, this run's is "
        f"{found.fingerprint}: grade into another folder, or --regrade to grade everyone "
        f"again under {found.fingerprint}{old}"
    )


def _graded_under(out: Path, student: str) -> str | None:
    """The fingerprint of the seed the student's results.json was graded under."""
    try:
        results = json.loads((out / "feedback" / student / "results.json").read_text())
        return results["extra_data"]["seed_fingerprint"]
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _grade_student(
    folder: Path, name: str, out: Path, names, options: Options, draw: list[str]
) -> dict:
    """One student, by a grader process of its own under a time budget: a row of scores.csv."""
    feedback = out / "feedback" / name
    feedback.mkdir(parents=True, exist_ok=True)
    results_path = feedback / "results.json"
    results_path.unlink(missing_ok=True)
    command = [
        sys.executable, "-m", "raykit_grading", "grade", str(folder),
        "-o", str(results_path), "--feedback", str(feedback),
        "--wall-seconds", str(options.limits.wall_seconds),
        "--total-seconds", str(options.total_seconds), *draw,
    ]  # fmt: skip
    if options.child_python:
        command += ["--child-python", options.child_python]
    if names:
        command += ["--only", *names]
    row = {"student": name}
    try:
        run = subprocess.run(
            command,
            capture_output=True,
            text=True,
            encoding="utf-8",
            errors="replace",  # a folder name that is not UTF-8 is printed as it is
            timeout=options.total_seconds + MARGIN_SECONDS,
            stdin=subprocess.DEVNULL,
        )
    except subprocess.TimeoutExpired as exc:
        _keep_log(out, name, exc.stderr)
        return {**row, "status": "could not grade: its grader went over its time budget"}
    _keep_log(out, name, run.stderr)
    if run.returncode != 0 or not results_path.is_file():
        last = (run.stderr.strip().splitlines() or [f"exit status {run.returncode}"])[-1]
        return {**row, "status": f"could not grade: {last[:300]}"}
    results = json.loads(results_path.read_text())
    _set_hidden_pictures_apart(results, feedback, out / HIDDEN_PICTURES / name)
    if results.get("extra_data", {}).get("sandbox", "").startswith("none"):  # none of it ran
        why = results["tests"][0]["output"].splitlines()[0] if results["tests"] else ""
        row["status"] = f"could not grade: {why or 'no raykit package in the folder'}"[:300]
    elif results.get("extra_data", {}).get("does_not_import"):
        row["status"] = DOES_NOT_IMPORT
    else:
        row["status"] = "graded"
    row["score"] = results["score"]
    row["max_score"] = sum(t["max_score"] for t in results["tests"])
    row.update({t["number"]: t["score"] for t in results["tests"]})
    return row


def _keep_log(out: Path, name: str, log: str | bytes | None) -> None:
    """Keep what the student's grader said on stderr in ``OUT/logs/<student>.log``, for the
    instructor: its sandbox, its own peak memory and how often the container's OOM killer
    fired, what it set aside in a quarantine, why it could not grade."""
    if isinstance(log, bytes):  # what a grader stopped part way said
        log = log.decode("utf-8", "replace")
    path = out / LOGS / f"{name}.log"
    path.parent.mkdir(exist_ok=True)
    path.write_text(log or "", encoding="utf-8", errors="replace")


def _set_hidden_pictures_apart(results: dict, feedback: Path, hidden: Path) -> None:
    """Move the hidden tests' pictures out of the student's feedback folder, which may then
    be handed to the student as it is (as Gradescope shows them only what is visible)."""
    shutil.rmtree(hidden, ignore_errors=True)
    for test in results["tests"]:
        picture = feedback / f"{test['number']}.png"
        if test.get("visibility") != VISIBLE and picture.is_file():
            hidden.mkdir(parents=True, exist_ok=True)
            picture.replace(hidden / picture.name)


def _write_all(path: Path, header: list[str], rows: dict[str, dict]) -> None:
    temporary = path.with_suffix(".csv.part")
    with open(temporary, "w", newline="", **NAMES_AS_BYTES) as stream:
        writer = csv.writer(stream)
        writer.writerow(header)
        for name in sorted(rows):
            writer.writerow([rows[name].get(k, "") for k in header])
    os.replace(temporary, path)


def _progress(iterable, total: int):
    try:
        from tqdm import tqdm
    except ImportError:
        return iterable
    return tqdm(iterable, total=total, unit="student", desc="grading", file=sys.stderr)

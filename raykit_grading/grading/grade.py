"""Grading one submission: every test of the catalog, in a sandbox, into Gradescope's results.

The submission is first staged (:mod:`raykit_grading.grading.submissions`: plain files only, links
and special files left out) into a private workspace (:mod:`raykit_grading.sandbox.workspace`), then
a sandbox is checked to work (:meth:`Sandbox.check`) before any test runs. Each test draws its
inputs from the assignment's secret seed (:mod:`raykit_grading.assignment.seeds`;
:meth:`GradingTest.graded_inputs`: nothing shipped to students answers it, and a regrade gets
the same inputs), runs the submission's code on them in a sandbox of its own, and compares what
comes back with the same task run here by the reference raykit: arrays within a tolerance,
renders with :mod:`raykit_grading.kit.compare`; a render that is not right is also compared with
the classic mistakes (:mod:`raykit_grading.assignment.mistakes`), and a mistake found there costs
that test its points (a systematic mistake is not float noise), saying why.

A test that fails, for whatever reason, fails alone: every other test keeps its score. If the
grader itself fails on a test, that test says so ("not graded"), the others are graded, and
the run ends with :class:`NotGraded` so that the command exits non-zero. If no sandbox can be
made, nothing is graded (:class:`GradingImpossible`).

results.json follows Gradescope's specification (score, execution_time, output, tests with
name, number, score, max_score, status, output, output_format, visibility). It is written by
this process, last and atomically. A visible render's output is HTML with the captioned
feedback picture (yours | expected | where they differ) inline; hidden tests show their score
and message only, never a picture or what the code printed. What is shown at once says
nothing of a hidden test: the top output sums the visible tests only, and
``execution_time`` is the time up to the last visible test (every hidden test runs after
them). At the end the grader says on stderr (Gradescope's stdout, which students do not see)
its own peak memory and how often the container's OOM killer fired while it graded
(:mod:`raykit_grading.sandbox.budgets`).
"""

from __future__ import annotations

import json
import os
import re
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from raykit.io.images import quantize, save_image
from raykit_grading.assignment.catalog import (
    HIDDEN_SCENES,
    SCENES,
    VISIBLE,
    GradingTest,
    by_name,
)
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.assignment.references import array_mistakes, expected
from raykit_grading.assignment.seeds import fingerprint, new_seed
from raykit_grading.grading.results import (
    NOT_IMPORTED,
    html_output,
    not_graded_results,
    stage_lines,
    test_entry,
    withheld,
    write_results,
)
from raykit_grading.grading.submissions import SubmissionError, stage
from raykit_grading.kit import tasks
from raykit_grading.kit.compare import (
    DEFAULT_SCORING,
    Scoring,
    describe_inputs,
    judge_arrays,
    judge_image,
)
from raykit_grading.sandbox.base import Limits, Sandbox
from raykit_grading.sandbox.budgets import GRADER_MEMORY, grader_peak
from raykit_grading.sandbox.isolation import IsolationUnavailable
from raykit_grading.sandbox.kinds import choose_sandbox
from raykit_grading.sandbox.workspace import Workspace

TOTAL_SECONDS = 480.0  # what all of one submission's tests may take together


class GradingImpossible(RuntimeError):
    """Nothing can be graded here (no sandbox, no clone); the message says why and the fix."""


class NotGraded(RuntimeError):
    """Some tests could not be graded because the grader failed on them (``results`` holds
    the rest, graded)."""

    def __init__(self, message: str, results: dict) -> None:
        super().__init__(message)
        self.results = results


@dataclass(frozen=True)
class Options:
    child_python: str | None = None
    limits: Limits = Limits()
    total_seconds: float = TOTAL_SECONDS
    scoring: Scoring = DEFAULT_SCORING


def check_clone() -> None:
    """The grader reads the course repository's scenes; say so plainly when they are absent."""
    for folder in (SCENES, HIDDEN_SCENES):
        if not folder.is_dir():
            raise GradingImpossible(
                f"the grader needs a clone of the course repository ({folder} not found); "
                "run it from a clone (pip install -e .)"
            )


def preflight(options: Options = Options()) -> None:
    """Before any student is graded: the scenes are there and a sandbox works here."""
    check_clone()
    with Workspace() as workspace:
        empty = workspace / "nothing"
        empty.mkdir(mode=0o755)
        try:
            choose_sandbox(empty, workspace, options.child_python, options.limits)
        except IsolationUnavailable as exc:
            raise GradingImpossible(str(exc)) from None


def grade(
    submission: Path,
    *,
    names: list[str] | None = None,
    feedback: Path | None = None,
    seed: int | None = None,
    options: Options = Options(),
    progress=None,
) -> dict:
    """Grade a submission folder; returns Gradescope's results as a dict.

    ``seed``: the assignment's seed (None: a draw of its own, for this run only). Raises
    :class:`GradingImpossible` if nothing can be graded here, :class:`NotGraded` (with
    the results of the rest) if the grader failed on some tests.
    """
    start = time.perf_counter()
    tests = by_name(names)
    seed = new_seed() if seed is None else seed
    check_clone()
    results, notes, failures = [], [], []
    sandbox, visible_done = None, None  # visible_done: when the last visible test was graded
    sandbox_kind = "none: nothing of the submission was run"
    broken = ""  # why the submission's raykit does not import ("" if it does)
    unimported: list[str] = []  # which of its modules do not import, and why
    with Workspace() as workspace:
        try:
            staged = stage(Path(submission), workspace / "submission")
            notes = staged.notes
            package = staged.package
            problem = staged.problem or "no raykit package (expected raykit/__init__.py)"
        except SubmissionError as exc:
            package, problem = None, f"the submission could not be taken in: {exc}"
        except OSError as exc:  # a shape of folder the staging did not foresee: theirs
            package, problem = None, f"the submission could not be read: {exc.strerror}"
        if package is None:
            results = [test_entry(t, 0.0, problem) for t in tests]
        else:
            try:
                sandbox = choose_sandbox(
                    staged.root, workspace, options.child_python, options.limits
                )
            except IsolationUnavailable as exc:
                raise GradingImpossible(str(exc)) from None
            sandbox_kind = sandbox.description
            print(f"raykit_grading: sandbox: {sandbox_kind}", file=sys.stderr)
            deadline = time.monotonic() + options.total_seconds  # the import check's too
            broken, unimported = _import_error(sandbox, options, deadline)
            notes = notes + unimported
            graded = {t.key: test_entry(t, 0.0, NOT_IMPORTED) for t in tests} if broken else {}
            for test in [] if broken else _visible_first(tests):
                if test.visibility != VISIBLE and visible_done is None:
                    visible_done = time.perf_counter()
                try:
                    graded[test.key] = _grade_one(sandbox, test, seed, feedback, options, deadline)
                except Exception as exc:  # noqa: BLE001 - one test's failure stays its own
                    failures.append(f"{test.key}: {type(exc).__name__}: {exc}")
                    graded[test.key] = test_entry(
                        test,
                        0.0,
                        "not graded: the autograder failed on this test (not your "
                        "code's fault); your instructor has to regrade it",
                    )
                if progress:
                    progress(test)
            results = [graded[test.key] for test in tests]  # in the catalog's order
    summary = [f"raykit autograder: {len(tests)} tests"]
    summary += [f"Note: {note}" for note in notes]
    if package is None:  # the submission's shape, said once at the top as well
        summary.append(problem)
    if broken:  # said once here; every test says it was not run
        summary.append(f"raykit does not import, so no test was run: {broken}")
    summary += stage_lines(tests, results)
    hidden = {t.key for t in tests if t.visibility != VISIBLE}
    shown_failures = [f for f in failures if f.split(":")[0] not in hidden]
    if shown_failures:  # a hidden test's failure is the instructor's to see (stderr, exit 3)
        summary.append(f"{len(shown_failures)} test(s) could not be graded; they need a regrade")
    _say_what_it_cost(sandbox)
    graded = {
        "score": round(sum(r["score"] for r in results), 4),
        "execution_time": round((visible_done or time.perf_counter()) - start, 2),
        "output": "\n".join(summary),
        "visibility": "visible",
        "stdout_visibility": "hidden",
        # the seed's fingerprint, never the seed: hidden results reach students after the due
        # date, and the seed would let them draw the hidden tests' inputs for a regrade
        "extra_data": {
            "seed_fingerprint": fingerprint(seed),
            "not_graded": failures,
            "sandbox": sandbox_kind,
            **({"does_not_import": broken} if broken else {}),
            **({"modules_not_imported": unimported[0]} if unimported else {}),
        },
        "tests": results,
    }
    if failures:
        raise NotGraded("; ".join(failures), graded)
    return graded


def _say_what_it_cost(sandbox) -> None:
    """One line on stderr: the grader's own peak memory against the share it keeps, and how
    often the container's OOM killer fired while it graded (where its cgroup says)."""
    line = (
        f"raykit_grading: the grader's peak memory: {grader_peak() // 2**20} MB of the "
        f"{GRADER_MEMORY // 2**20} MB it keeps"
    )
    now = sandbox.oom_count() if sandbox is not None else None
    if now is not None and sandbox.oom_before is not None:
        line += f"; the container's OOM killer fired {now - sandbox.oom_before} times"
    print(line, file=sys.stderr)


def _grade_one(
    sandbox: Sandbox,
    test: GradingTest,
    seed: int,
    feedback: Path | None,
    options: Options,
    deadline: float,
) -> dict:
    left = deadline - time.monotonic()
    if left <= 1:
        return test_entry(
            test,
            0.0,
            f"not run: all tests together may take {options.total_seconds:g} s, and your "
            "code used that time up in the tests before this one",
        )
    spec, arrays, files = test.graded_inputs(seed)
    ran = sandbox.run(
        test.task, spec, arrays, files, wall_seconds=min(options.limits.wall_seconds, left)
    )
    # what the grader had to force to remove is said on visible tests (a hidden test's code
    # could choose what to leave by its inputs)
    note = f"\nNote: {ran.left}" if ran.left and test.visibility == VISIBLE else ""
    if ran.outputs is None:
        problem = ran.problem if test.visibility == VISIBLE else withheld(ran.problem)
        return test_entry(test, 0.0, problem + note, ran.output)
    if test.kind == "image":
        return _image_result(test, seed, ran.outputs, feedback, options.scoring, ran.output, note)
    want = expected(test.name, seed)
    verdict = judge_arrays(ran.outputs, want, tolerance=test.tolerance)
    if verdict.share < 1.0:  # say why: the inputs, the mistake, where it starts
        verdict = judge_arrays(
            ran.outputs,
            want,
            spec=spec,
            arrays=arrays,
            tolerance=test.tolerance,
            mistakes=array_mistakes(test, seed),
            callees=_callees(sandbox, test, spec, arrays, files, deadline, options),
            caller=CALLERS.get(test.task, ""),
            hidden=test.visibility != VISIBLE,
        )
    score = test.points if verdict.share >= 1.0 else 0.0  # array tests: all or nothing
    return _diagnosed(test_entry(test, score, verdict.message + note, ran.output), verdict)


IMPORT_FAILURES = ("your code stopped with an error", "not written yet", "your code crashed")


def _import_error(sandbox: Sandbox, options: Options, deadline: float) -> tuple[str, list]:
    """Why the submission's raykit does not import at all, with what it printed ("" if it
    does; a hang or a memory blow-up at import is left to each test to say), and a note
    naming the modules that do not import when others do (the tests that use them fail, each
    saying why). It takes its time from the submission's total, as a test does."""
    left = deadline - time.monotonic()
    try:
        ran = sandbox.run(
            "imports", {}, {}, wall_seconds=max(1.0, min(options.limits.wall_seconds, left))
        )
    except Exception:  # noqa: BLE001 - the grader's trouble: each test meets and says it
        return "", []
    if ran.outputs is not None:
        flags = np.asarray(ran.outputs.get("imports", ()), dtype=float).ravel()
        if flags.shape != (len(tasks.IMPORTED),):
            return "", []
        failing = [name for name, ok in zip(tasks.IMPORTED, flags, strict=True) if ok != 1.0]
        if not failing:
            return "", []
        one = len(failing) == 1
        causes = list(dict.fromkeys(re.findall(r"^import failed: (.*)$", ran.output, re.M)))
        why = f" ({'; '.join(causes[:3])})" if causes else ""
        return "", [
            f"{', '.join(failing)}: {'does' if one else 'do'} not import{why}; the tests that "
            f"use {'it' if one else 'them'} fail"
        ]
    if not ran.problem.startswith(IMPORT_FAILURES):
        return "", []
    lines = ran.output.strip().splitlines()
    theirs = next((i for i, line in enumerate(lines) if "/submission/" in line), None)
    if theirs is not None:  # from the submission's first frame: the grader's own say nothing
        lines = ["Traceback (most recent call last):", *lines[theirs:]]
    printed = "\n".join(lines[-30:])
    return ran.problem + (f"\n{printed}" if printed else ""), []


def _diagnosed(entry: dict, verdict) -> dict:
    """The classic mistake a verdict names, as a field of the test's entry (``extra_data``:
    ``mistake``, its key, or its words for a one-pixel shift; ``says``; ``where``): what a
    class report counts, never parsed back from the message."""
    if verdict.diagnosed is not None:
        says, where = verdict.diagnosed
        key = next((m.key for m in MISTAKES if m.says == says), None)
        if key is None and says.startswith("the picture is shifted by one pixel"):
            key = "shifted_by_one"
        entry["extra_data"] = {"mistake": key or says, "says": says, "where": where}
    return entry


def _visible_first(tests: list[GradingTest]) -> list[GradingTest]:
    """The order tests run in: every visible test before any hidden one, so that nothing a
    hidden test's code does (or leaves, or how long it takes) can reach a visible test's
    output."""
    return [t for t in tests if t.visibility == VISIBLE] + [
        t for t in tests if t.visibility != VISIBLE
    ]


# the student function each array task calls first, as the callee lines name it
CALLERS = {
    "line_rays": "line_rays",
    "rays_through": "rays_through",
    "thin_lens_rays": "thin_lens_rays",
    "perturbed_direction": "perturbed_direction",
    "glossy_reflect": "glossy_reflect",
}


def _callees(sandbox, test, spec, arrays, files, deadline, options) -> list:
    """(name, the submission's results or None, the reference's) of each function the test's
    function calls, run on the same inputs."""
    found = []
    for callee in test.callees:
        left = deadline - time.monotonic()
        if left <= 1:
            break
        their_spec, their_arrays = callee.inputs(spec, arrays)
        ran = sandbox.run(
            callee.task,
            their_spec,
            their_arrays,
            files,
            wall_seconds=min(options.limits.wall_seconds, left),
        )
        want = tasks.TASKS[callee.task](json.loads(json.dumps(their_spec)), their_arrays)
        found.append((callee.name, ran.outputs, {k: np.asarray(v) for k, v in want.items()}))
    return found


def _image_result(
    test: GradingTest,
    seed: int,
    got: dict,
    feedback: Path | None,
    scoring: Scoring,
    printed="",
    note="",
) -> dict:
    want = quantize(expected(test.name, seed)["rgb"])
    rgb = got.get("rgb")
    if rgb is None or rgb.shape != want.shape:
        if test.visibility != VISIBLE:  # its shape is the code's choice: not shown
            return test_entry(test, 0.0, "the image is not of the expected size (a hidden test)")
        shape = None if rgb is None else rgb.shape
        return test_entry(test, 0.0, f"the image has shape {shape}, expected {want.shape}")
    if not np.isfinite(rgb).all():
        return test_entry(test, 0.0, "the image holds NaN or infinity")
    mine = quantize(rgb)
    mistakes = (
        (
            (m.says, quantize(expected(test.name, seed, m.key)["rgb"]), m.where)
            for m in MISTAKES
            if m.in_renders and m.tried_on(test.stage)
        )
        if test.mistakes
        else ()
    )
    hidden = test.visibility != VISIBLE
    inputs = "" if hidden else describe_inputs(*test.graded_inputs(seed)[:2])
    verdict = judge_image(mine, want, mistakes, scoring, inputs)
    message = verdict.message + note
    if feedback is not None:
        feedback.mkdir(parents=True, exist_ok=True)
        path = feedback / f"{test.key}.png"
        save_image(verdict.picture, path)
        if not hidden:  # a hidden test's picture is the instructor's alone: not named to students
            message += f"\nfeedback picture (yours | expected | where they differ): {path.name}"
    entry = _diagnosed(test_entry(test, test.points * verdict.share, message, printed), verdict)
    if test.visibility == VISIBLE:  # hidden tests show nothing a student could copy
        entry["output"] = html_output(entry["output"], verdict.picture)
        entry["output_format"] = "html"
    return entry


def grade_to_file(submission: Path, output: Path, **options) -> int:
    """Grade and write results.json: the exit status (0 graded, whatever the score, even a
    submission with nothing to grade; 3 some or all tests could not be graded; results.json
    says which)."""
    names = options.get("names")
    reserve = _reserve_room(Path(output).parent)
    try:
        results = grade(submission, **options)
        status = 0
    except NotGraded as exc:
        results, status = exc.results, 3
        print(f"raykit_grading: some tests could not be graded: {exc}", file=sys.stderr)
    except GradingImpossible as exc:
        results, status = not_graded_results(str(exc), by_name(names)), 3
        print(f"raykit_grading: error: cannot grade: {exc}", file=sys.stderr)
    finally:
        if reserve is not None:
            reserve.unlink(missing_ok=True)
    write_results(results, output)
    return status


RESERVED_BYTES = 16 * 2**20  # more than the largest results.json, pictures and all


def _reserve_room(folder: Path) -> Path | None:
    """Hold room for results.json beside it while grading (a file of written blocks, let go
    just before results.json is written), so that whatever filled the disk meanwhile, the
    results can still be written."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle, name = tempfile.mkstemp(prefix=".reserved-for-results.", dir=folder)
        with os.fdopen(handle, "wb") as stream:
            stream.write(bytes(RESERVED_BYTES))
        return Path(name)
    except OSError:
        return None  # the disk is full already: results.json is tried all the same

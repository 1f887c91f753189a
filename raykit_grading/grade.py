"""Grading one submission: every test of the catalog, in a sandbox, into Gradescope's results.

The expected results are the catalog's tasks run here with the reference raykit (cached for
the run); the submission's results come back from :class:`raykit_grading.sandbox.Sandbox` as plain
arrays and are checked here: shape, finite numbers, values. Image results are compared with
:mod:`raykit_grading.compare`; a failed render is also compared with the classic mistakes
(:mod:`raykit_grading.mistakes`) so that feedback can name one.

results.json follows Gradescope's specification (score, execution_time, output, tests with
name, score, max_score, output, visibility, status). It is written by this process, last and
atomically, whatever the submission did; if grading itself fails, it still says so in a valid
results.json with score 0.
"""

from __future__ import annotations

import functools
import json
import os
import sys
import tempfile
import time
import traceback
from pathlib import Path

import numpy as np

from raykit.images import quantize, save_image
from raykit_grading import child
from raykit_grading.catalog import TESTS, GradingTest, by_name
from raykit_grading.compare import (
    DEFAULT_SCORING,
    Scoring,
    check_arrays,
    compare_images,
    feedback_picture,
    strict_fraction,
)
from raykit_grading.mistakes import MISTAKES
from raykit_grading.sandbox import Limits, Sandbox

DIAGNOSE_FROM = 0.95  # a mistake is named only if it explains this much of the image
STRICTLY_RIGHT = 0.99  # an image this close to the reference, pixel for pixel, needs no diagnosis


def find_package(submission: Path) -> Path | None:
    """The submission's ``raykit`` package folder: at its top, or one folder down."""
    for candidate in [submission / "raykit", *sorted(submission.glob("*/raykit"))]:
        if (candidate / "__init__.py").is_file():
            return candidate
    return None


@functools.cache
def expected(test_name: str, mistake: str | None = None) -> dict[str, np.ndarray]:
    """The reference results of a test (optionally with a classic mistake made)."""
    test = next(t for t in TESTS if t.name == test_name)
    spec, arrays, files = test.inputs()
    spec = json.loads(json.dumps(spec))
    if "folder" in spec:  # the parent reads the textures where they are
        with tempfile.TemporaryDirectory() as folder:
            for relative, source in files.items():
                target = Path(folder) / relative
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(source.read_bytes())
            spec["folder"] = str(Path(folder) / spec["folder"])
            return _run_reference(test, spec, arrays, mistake)
    return _run_reference(test, spec, arrays, mistake)


def _run_reference(test: GradingTest, spec, arrays, mistake: str | None):
    if mistake is None:
        return child.TASKS[test.task](spec, arrays)
    wrong = next(m for m in MISTAKES if m.key == mistake)
    with wrong.active():
        outputs = child.TASKS[test.task](spec, arrays)
    return {k: wrong.after(v) for k, v in outputs.items()}


def _image_result(
    test: GradingTest, got: dict, feedback: Path | None, scoring: Scoring
) -> tuple[float, str]:
    want = quantize(expected(test.name)["rgb"])
    rgb = got.get("rgb")
    if rgb is None or rgb.shape != want.shape:
        shape = None if rgb is None else rgb.shape
        return 0.0, f"the image has shape {shape}, expected {want.shape}"
    if not np.issubdtype(rgb.dtype, np.number) or not np.isfinite(rgb).all():
        return 0.0, "the image holds NaN, infinity or values that are not numbers"
    mine = quantize(rgb)
    result = compare_images(mine, want, scoring)
    score = result.score(scoring)
    lines = [
        f"{result.fraction:.2%} of pixels match the reference (full marks from "
        f"{scoring.full_at:.1%}, none below {scoring.none_below:.0%}); "
        f"PSNR {result.psnr:.1f} dB"
    ]
    if feedback is not None:
        feedback.mkdir(parents=True, exist_ok=True)
        picture = feedback / f"{test.name.split()[0]}.png"
        save_image(feedback_picture(mine, want, result.matched), picture)
        lines.append(f"feedback picture (yours | reference | mismatches): {picture.name}")
    if test.mistakes:
        diagnosis = diagnose(test, mine, want)
        if diagnosis:
            lines.append(diagnosis if score < 1 else f"Full marks, but note: {diagnosis}")
    return score, "\n".join(lines)


def diagnose(test: GradingTest, mine: np.ndarray, want: np.ndarray) -> str | None:
    """Name the classic mistake whose image explains the submission's better than the
    reference does, pixel for pixel (strictly, so that even a half-pixel shift shows)."""
    best, best_fraction = None, max(strict_fraction(mine, want), DIAGNOSE_FROM)
    if best_fraction >= STRICTLY_RIGHT:
        return None
    for mistake in MISTAKES:
        wrong = quantize(expected(test.name, mistake.key)["rgb"])
        if wrong.shape != mine.shape:
            continue
        matched = strict_fraction(mine, wrong)
        if matched > best_fraction:
            best, best_fraction = mistake, matched
    if best is None:
        return None
    return (
        f"Your image matches what the renderer gives when {best.says} "
        f"({best_fraction:.1%} of pixels)."
    )


def grade(
    submission: Path,
    *,
    child_python: str | None = None,
    names: list[str] | None = None,
    feedback: Path | None = None,
    limits: Limits | None = None,
    scoring: Scoring = DEFAULT_SCORING,
) -> dict:
    """Grade a submission folder; returns Gradescope's results as a dict."""
    start = time.perf_counter()
    tests = by_name(names)
    package = find_package(Path(submission))
    results = []
    if package is None:
        message = "no raykit package found in the submission (expected raykit/__init__.py)"
        results = [_result(t, 0.0, message) for t in tests]
    else:
        with Sandbox(child_python or sys.executable, limits) as sandbox:
            for test in tests:
                results.append(_grade_one(sandbox, package, test, feedback, scoring))
    return {
        "score": round(sum(r["score"] for r in results), 4),
        "execution_time": round(time.perf_counter() - start, 2),
        "output": f"raykit autograder: {len(tests)} tests",
        "visibility": "visible",
        "stdout_visibility": "hidden",
        "tests": results,
    }


def _grade_one(
    sandbox: Sandbox, package: Path, test: GradingTest, feedback: Path | None, scoring: Scoring
) -> dict:
    spec, arrays, files = test.inputs()
    ran = sandbox.run(package, test.task, spec, arrays, files)
    if ran.outputs is None:
        return _result(test, 0.0, ran.problem, ran.output)
    if test.kind == "image":
        share, message = _image_result(test, ran.outputs, feedback, scoring)
        return _result(test, test.points * share, message)
    passed, message = check_arrays(ran.outputs, expected(test.name))
    return _result(test, test.points if passed else 0.0, f"{message} ({test.tolerance})")


def _result(test: GradingTest, score: float, message: str, output: str = "") -> dict:
    text = message if not output.strip() else f"{message}\n--- your code printed ---\n{output}"
    return {
        "name": test.name,
        "score": round(score, 4),
        "max_score": test.points,
        "output": text[:4000],
        "visibility": test.visibility,
        "status": "passed" if score >= test.points else "failed",
    }


def failed_results(why: str) -> dict:
    """A valid results.json when grading itself could not run."""
    return {
        "score": 0,
        "execution_time": 0,
        "visibility": "visible",
        "output": f"The autograder could not grade this submission: {why}",
        "tests": [_result(t, 0.0, "not graded: the autograder failed") for t in TESTS],
    }


def write_results(results: dict, path: Path) -> None:
    """Write results.json whole or not at all."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=".results.", dir=path.parent)
    with os.fdopen(handle, "w") as stream:
        json.dump(results, stream, indent=2)
    os.replace(temporary, path)


def grade_to_file(submission: Path, output: Path, **options) -> dict:
    """Grade and write results.json, always: a crash of the grader becomes a score of 0."""
    try:
        results = grade(submission, **options)
    except Exception as exc:  # noqa: BLE001 - the results file must exist whatever happened
        traceback.print_exc()
        results = failed_results(f"{type(exc).__name__}: {exc}")
    write_results(results, output)
    return results

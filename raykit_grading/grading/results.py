"""Gradescope's results.json: one entry per test, the file written whole, and the words a
hidden test may say.

The format is Gradescope's ("Autograder Specifications"): a ``score``, an ``output``, and
``tests``, each with ``name``, ``number``, ``score``, ``max_score``, ``output`` (plain text, or
HTML with ``output_format: "html"`` when it carries a picture) and ``visibility``. The local
``grade`` and ``batch`` commands write the same file.
"""

from __future__ import annotations

import base64
import html
import io
import json
import os
import re
import tempfile
from pathlib import Path

import numpy as np

from raykit_grading.assignment.catalog import TESTS, VISIBLE, GradingTest
from raykit_grading.kit.compare import feedback_html

OUTPUT_LIMIT = 4000  # characters of text per test (pictures come on top, as HTML)


# what a hidden test may say when the code failed to give results: the grader's own words
# only (the code's error message, names and sizes could carry the test's inputs out)
WITHHELD_KINDS = (
    "not written yet",
    "your code stopped with an error",
    "your code used up its CPU time",
    "your code wrote a file larger than allowed",
    "your code was killed (too much memory or time?)",
    "your code crashed",
    "your code used more memory than allowed",
    "returned something that is not plain arrays",
    "your code used more disk than allowed",
)


def withheld(problem: str) -> str:
    """A hidden test's problem in the grader's words only: what kind of failure, nothing the
    code said or chose (names, sizes, its error message)."""
    for kind in WITHHELD_KINDS:
        if problem.startswith(kind):
            return f"{kind} (a hidden test: details are not shown)"
    if problem.startswith(("took longer than", "returned more than")):
        return problem  # the grader's limits, in its own words
    return "your code did not give results (a hidden test: details are not shown)"


def html_output(text: str, picture: np.ndarray | None) -> str:
    """A test's output for Gradescope: :func:`feedback_html`, the picture inline."""
    source = None
    if picture is not None:
        from PIL import Image

        png = io.BytesIO()
        Image.fromarray(picture).save(png, format="PNG", optimize=True)
        source = "data:image/png;base64," + base64.b64encode(png.getvalue()).decode()
    return feedback_html(text, source)


def split_html_output(output: str) -> tuple[str, str | None]:
    """A test's output again as (text, picture's data: URL or None): the inverse of
    :func:`html_output`, for platforms that show pictures apart from the text."""
    if not output.startswith("<pre"):
        return output, None
    text = re.search(r"<pre[^>]*>(.*?)</pre>", output, re.DOTALL)
    picture = re.search(r'<img src="([^"]*)"', output)
    return (
        html.unescape(text.group(1)) if text else "",
        html.unescape(picture.group(1)) if picture else None,
    )


def test_entry(test: GradingTest, score: float, message: str, output: str = "") -> dict:
    """One test's entry in results.json; what the code printed is shown on visible tests only."""
    if output.strip() and test.visibility == VISIBLE:  # a hidden test's data never shows
        message = f"{message}\n--- your code printed ---\n{output}"
    return {
        "name": test.name,
        "number": test.key,
        "score": round(score, 4),
        "max_score": test.points,
        "output": message[:OUTPUT_LIMIT],
        "visibility": test.visibility,
        "status": "passed" if score >= test.points else "failed",
    }


def write_results(results: dict, path: Path) -> None:
    """Write results.json whole or not at all."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, temporary = tempfile.mkstemp(prefix=".results.", dir=path.parent)
    with os.fdopen(handle, "w") as stream:
        json.dump(results, stream, indent=2)
    os.replace(temporary, path)


def not_graded_results(why: str, tests: list[GradingTest] | None = None) -> dict:
    """results.json for a run that could grade nothing: it says so on every test (and the
    command exits non-zero); it is never a score the student earned."""
    message = f"NOT GRADED: the autograder could not run here ({why}); ask your instructor"
    return {
        "score": 0,
        "execution_time": 0,
        "output": message,
        "visibility": "visible",
        "stdout_visibility": "hidden",
        "extra_data": {"not_graded": [why]},
        "tests": [test_entry(t, 0.0, message) for t in (tests or TESTS)],
    }


NOT_IMPORTED = "not run: raykit does not import"


def stage_lines(tests: list[GradingTest], entries: list[dict]) -> list[str]:
    """The top output's sum-up, shown at once: one line per stage of its visible tests' points
    and passes, then one line saying how many hidden tests there are and their points, and
    nothing of how they went (that is each hidden test's own, shown with its visibility)."""
    lines = []
    for stage in dict.fromkeys(t.stage for t in tests):
        mine = [(t, e) for t, e in zip(tests, entries, strict=True)
                if t.stage == stage and t.visibility == VISIBLE]  # fmt: skip
        if not mine:
            continue
        earned = sum(e["score"] for _, e in mine)
        passed = sum(e["score"] >= t.points for t, e in mine)
        lines.append(
            f"Stage {stage}: {earned:.4g} of {sum(t.points for t, _ in mine):.4g} points, "
            f"{passed} of {len(mine)} visible tests pass"
        )
    hidden = [t for t in tests if t.visibility != VISIBLE]
    if hidden:
        lines.append(
            f"Hidden tests: {len(hidden)}, {sum(t.points for t in hidden):.4g} points (how they "
            "went is not shown here)"
        )
    return lines

"""The class report and the students' pages a batch writes (raykit_grading.grading.report): on
the class tests/conftest.py grades once (``graded_class``, shared with test_batch.py), the
scores, each test's pass rate by stage, the diagnosed mistakes ranked with an example picture,
who could not be graded and why; each student's page with the grade's numbers."""

from __future__ import annotations

import html
import re
from urllib.parse import unquote

from conftest import CLASS_TESTS
from raykit_grading.grading.report import (
    DOES_NOT_IMPORT,
    GRADED,
    NOT_A_SUBMISSION,
    class_summary,
)
from raykit_grading.grading.results import NOT_IMPORTED


def test_the_class_report_shows_scores_pass_rates_mistakes_and_who_was_not_graded(graded_class):
    out, _ = graded_class
    page = html.unescape((out / "report.html").read_text())
    for plot in ("report/scores.png", "report/pass_rates.png"):
        assert f"src='{plot}'" in page
        assert (out / plot).read_bytes().startswith(b"\x89PNG")
    assert (
        "9 submissions: 8 graded, 1 whose raykit does not import (0 points); 1 entry is not a "
        "submission." in page
    )
    assert "Mean 3.6, median 3.0 of 7 points" in page  # 7 7 7 1 2 2 3 3 0
    rates = dict(re.findall(r"<tr><td>(\d\.\d+) .*?<td class='n'>(\d+%)</td>", page))
    assert rates == {"2.3": "78%", "3.1": "67%", "3.6": "33%"}  # of the 9 students scored
    assert page.index("Stage 2 rays") < page.index("2.3 ray-sphere") < page.index("Stage 3")
    swapped = page.index("u and v are swapped")
    flipped = page.index("image rows are counted from the bottom")
    assert swapped < flipped  # two students, then one
    counts = re.findall(r"<td class='n'>(\d+)</td><td>(u and v|image rows)", page)
    assert counts == [("2", "u and v"), ("1", "image rows")]
    example = re.search(r"<img class='example' src='([^']+)'", page[swapped:]).group(1)
    assert (out / unquote(example)).is_file()  # a URL, relative to the report
    assert "bo</a>: raykit does not import, so no test ran (0 points)" in page
    assert re.search(r"SyntaxError[^<]*</code> in raykit/__init__\.py, line \d+</li>", page)
    assert re.search(
        r"cy</a>: raykit.mirrors, raykit.render, raykit.shading: do not import "
        r"\(SyntaxError: invalid syntax \(in raykit/mirrors\.py, line \d+\)\)",
        page,
    )
    assert "notes.txt: not a submission: not a folder or a zip" in page


def test_each_student_gets_the_self_checks_page_with_the_grades_numbers(graded_class):
    out, _ = graded_class
    mo = html.unescape((out / "feedback/mo/index.html").read_text())
    assert "1 of 3 tests pass: 2 of 7 points." in mo
    assert mo.index("FAIL: 3.1") < mo.index("FAIL: 3.6") < mo.index("pass: 2.3")
    assert '<img src="3.6.png"' in mo and (out / "feedback/mo/3.6.png").is_file()
    bo = html.unescape((out / "feedback/bo/index.html").read_text())
    assert bo.count(NOT_IMPORTED) == len(CLASS_TESTS)
    assert bo.count("SyntaxError") == 2  # said once
    grace = html.unescape((out / "feedback/Grace Hopper/index.html").read_text())
    assert "3 of 3 tests pass: 7 of 7 points." in grace


def test_the_class_summary_says_who_could_not_be_graded_and_counts_no_stray_entry():
    """What the graded class does not show: a submission the grader could not grade (counted,
    listed below), and strays in the plural, never counted as submissions."""
    stray = f"{NOT_A_SUBMISSION}: not a folder or a zip"
    rows = {
        "ada": {"status": GRADED},
        "bo": {"status": GRADED},
        "cy": {"status": DOES_NOT_IMPORT},
        "di": {"status": "could not grade: its grader went over its time budget"},
        "notes.txt": {"status": stray},
        "todo.txt": {"status": stray},
    }
    assert class_summary(rows) == (
        "4 submissions: 2 graded, 1 whose raykit does not import (0 points), 1 not graded "
        "(listed below); 2 entries are not a submission"
    )
    assert class_summary({"ada": {"status": GRADED}, "bo": {"status": GRADED}}) == (
        "2 submissions: 2 graded"
    )
    assert class_summary({"ada": {"status": GRADED}}) == "1 submission: 1 graded"

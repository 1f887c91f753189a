"""The class report a batch writes beside ``scores.csv``, and each student's feedback page.

``OUT/report.html`` (static HTML with its plots as PNG files in ``OUT/report/``: it opens
offline, from the folder as it is) shows at a glance:

* the scores: mean, median, the histogram;
* each test's pass rate, stage by stage (a bar chart and a table);
* the classic mistakes the grader diagnosed, ranked by how many students made them, each with
  where it is made and one example picture (a student's feedback picture of a test showing it);
  read from the field each test's entry carries (``extra_data``: ``mistake``, ``says``,
  ``where``), never from the messages' words;
* the students who could not be graded, and why; those whose raykit does not import, with the
  error, its file and line; those some of whose modules do not import, which, and why (their
  tests that need them fail); the entries that are not submissions;
* every student's score, linked to their page.

``OUT/feedback/<student>/index.html`` is the student's feedback as the page ``check.py`` writes
(:func:`raykit_grading.kit.compare.feedback_page`), from their results.json: the summary, the
failing tests with their messages and pictures, the passing ones.
"""

from __future__ import annotations

import html
import json
import os
import re
import statistics
from pathlib import Path
from urllib.parse import quote

from raykit_grading.assignment.catalog import VISIBLE, GradingTest
from raykit_grading.kit.compare import PAGE_STYLE, feedback_page

GRADED, DOES_NOT_IMPORT = "graded", "does not import"
NOT_A_SUBMISSION = "not a submission"  # a stray entry: listed, never counted as ungraded
STYLE = (
    PAGE_STYLE
    + """
table { border-collapse: collapse; margin: 0.4em 0 1em; }
th, td { border-bottom: 1px solid #ddd; padding: 0.25em 0.6em; text-align: left;
         vertical-align: top; }
th, td { overflow-wrap: normal; }
th, td.n, td.w { white-space: nowrap; }
@media (max-width: 40em) { td.b, th.b, td.w, th.w { display: none; } }
td.n { text-align: right; font-variant-numeric: tabular-nums; }
img.plot { max-width: 100%; height: auto; }
img.example { max-width: 22em; width: 100%; height: auto; image-rendering: pixelated; }
.bar { display: inline-block; height: 0.8em; background: #4c78a8; }
.scroll { overflow-x: auto; }
"""
)


def write_report(out: Path, tests: list[GradingTest], rows: dict[str, dict]) -> Path:
    """Write ``OUT/report.html``, its plots, and each graded student's feedback page; returns
    the report's path."""
    out = Path(out)
    results = {}
    for name, row in rows.items():
        path = out / "feedback" / name / "results.json"
        if row.get("status") in (GRADED, DOES_NOT_IMPORT) and path.is_file():
            results[name] = json.loads(path.read_text())
            (path.parent / "index.html").write_text(student_page(name, results[name], path.parent))
    plots = out / "report"
    plots.mkdir(exist_ok=True)
    total = sum(t.points for t in tests)
    scores = {n: float(rows[n].get("score") or 0) for n in results}
    _histogram(list(scores.values()), total, plots / "scores.png")
    rates = _pass_rates(tests, results)
    _rate_plot(tests, rates, plots / "pass_rates.png")
    page = out / "report.html"
    page.write_text(_page(out, tests, rows, results, scores, rates, total))
    return page


def _message(test: dict) -> str:
    """A test's message as text: an HTML output is :func:`feedback_html`'s ``<pre>``."""
    if test.get("output_format") != "html":
        return test["output"]
    found = re.search(r"<pre[^>]*>(.*?)</pre>", test["output"], re.S)
    return html.unescape(found.group(1)) if found else ""


def student_page(name: str, results: dict, folder: Path) -> str:
    """A student's feedback page (the self-check's page, with the grade's numbers)."""
    rows = []
    for test in results["tests"]:
        picture = folder / f"{test['number']}.png"
        shown = test.get("visibility") == VISIBLE and picture.is_file()
        rows.append({
            "name": test["name"],
            "points": test["max_score"],
            "share": test["score"] / test["max_score"] if test["max_score"] else 1.0,
            "message": _message(test),
            "picture": quote(picture.name) if shown else None,
        })  # fmt: skip
    return feedback_page(
        rows,
        heading=f"raykit: {_shown(name)}'s grade",
        tests="tests",
        note="Hidden tests say only what kind of failure they found.",
        top=results.get("output", ""),
    )


def _pass_rates(tests: list[GradingTest], results: dict[str, dict]) -> dict[str, float]:
    rates = {}
    for test in tests:
        entries = [
            t for r in results.values() for t in r["tests"] if t["number"] == test.key
        ]  # fmt: skip
        passed = sum(t["score"] >= t["max_score"] for t in entries)
        rates[test.key] = passed / len(entries) if entries else float("nan")
    return rates


def _mistakes(results: dict[str, dict], out: Path) -> list[dict]:
    """The diagnosed mistakes, most students first: what, where, who, which tests, an example
    picture (a visible render's, if one shows it; else any render's)."""
    found: dict[str, dict] = {}
    for name in sorted(results):
        for test in results[name]["tests"]:
            named = (test.get("extra_data") or {}).get("mistake")
            if not named:
                continue
            extra = test["extra_data"]
            mistake = found.setdefault(
                named,
                {"says": extra.get("says", named), "where": extra.get("where", ""),
                 "students": set(), "tests": set(), "example": None},
            )  # fmt: skip
            mistake["students"].add(name)
            mistake["tests"].add(test["number"])
            better = test.get("visibility") == VISIBLE  # in feedback/, else in hidden/
            picture = out / ("feedback" if better else "hidden") / name / f"{test['number']}.png"
            if picture.is_file() and (mistake["example"] is None or better):
                if mistake["example"] is None or not mistake["example"][2]:
                    mistake["example"] = (name, test["number"], better)
    return sorted(found.values(), key=lambda m: (-len(m["students"]), m["says"]))


def _histogram(scores: list[float], total: float, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot

    figure, axes = pyplot.subplots(figsize=(6.4, 3.0), dpi=100)
    bins = max(1, min(20, int(total) or 1))
    axes.hist(scores, bins=bins, range=(0, total or 1), color="#4c78a8", edgecolor="white")
    axes.set_xlabel(f"score (of {total:g} points)")
    axes.set_ylabel("students")
    axes.yaxis.get_major_locator().set_params(integer=True)
    axes.set_title(f"Scores of {len(scores)} students")
    figure.tight_layout()
    figure.savefig(path)
    pyplot.close(figure)


def _rate_plot(tests: list[GradingTest], rates: dict[str, float], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot

    stages = list(dict.fromkeys(t.stage for t in tests))
    colours = pyplot.get_cmap("tab10")
    height = 1.2 + 0.3 * ((len(stages) + 1) // 2) + 0.2 * len(tests)
    figure, axes = pyplot.subplots(figsize=(6.4, height), dpi=100, layout="constrained")
    labels = [t.key for t in tests][::-1]
    values = [0 if rates[t.key] != rates[t.key] else 100 * rates[t.key] for t in tests][::-1]
    colour = [colours(stages.index(t.stage)) for t in tests][::-1]
    axes.barh(labels, values, color=colour)
    axes.set_xlim(0, 100)
    axes.set_xlabel("students who pass (%)")
    axes.tick_params(axis="y", labelsize=7)
    axes.set_title("Each test's pass rate")
    handles = [pyplot.Rectangle((0, 0), 1, 1, color=colours(i)) for i in range(len(stages))]
    figure.legend(handles, [f"stage {s}" for s in stages], fontsize=7, loc="outside lower center",
                  ncols=2, frameon=False)  # fmt: skip
    figure.savefig(path)
    pyplot.close(figure)


def _number(value: float) -> str:
    return f"{value:.4g}"


def _order(key: str) -> tuple[int, ...]:
    """A test's number as numbers: 3.2 before 3.10."""
    return tuple(int(part) for part in key.split(".") if part.isdigit())


def _shown(name: str) -> str:
    """A student's name as the page shows it (a folder name that is not UTF-8, readable)."""
    return name.encode("utf-8", "surrogateescape").decode("utf-8", "replace")


def _url(name: str) -> str:
    """A folder name as a relative URL: its bytes, percent-encoded."""
    return quote(os.fsencode(name))


def _where(error: str) -> str:
    """`` in raykit/FILE, line N``: the last place in the student's files that a traceback
    names, or ""."""
    places = re.findall(r'File "[^"]*/submission/(raykit/[^"]+)", line (\d+)', error)
    return f" in {places[-1][0]}, line {places[-1][1]}" if places else ""


def _link(name: str) -> str:
    return f"feedback/{_url(name)}/index.html"


def _page(out, tests, rows, results, scores, rates, total) -> str:
    broken = sorted(n for n in results if rows[n]["status"] == DOES_NOT_IMPORT)
    others = sorted(n for n in rows if n not in results)
    values = list(scores.values())

    def e(text: str) -> str:
        return html.escape(_shown(text))

    parts = [
        "<!doctype html><html lang='en'><meta charset='utf-8'>",
        "<meta name='viewport' content='width=device-width, initial-scale=1'>",
        "<title>raykit: the class report</title>",
        f"<style>{STYLE}</style>",
        "<h1>raykit: the class report</h1>",
        f"<p class='summary'><strong>{e(class_summary(rows))}.</strong>"
        + (
            f" Mean {statistics.mean(values):.1f}, median "
            f"{statistics.median(values):.1f} of {_number(total)} points."
            if values
            else ""
        )
        + " Each student's name links to their feedback page.</p>",
        "<h2>Scores</h2>",
        "<img class='plot' src='report/scores.png' alt='histogram of the scores'>",
        "<h2>Each test's pass rate, by stage</h2>",
        "<img class='plot' src='report/pass_rates.png' alt='pass rate of each test'>",
    ]
    for stage in dict.fromkeys(t.stage for t in tests):
        parts.append(f"<h3>Stage {e(stage)}</h3><div class='scroll'><table>")
        parts.append(
            "<tr><th>test</th><th>points</th><th class='w'>shown</th><th>pass</th>"
            "<th class='b'></th></tr>"
        )
        for test in (t for t in tests if t.stage == stage):
            rate = rates[test.key]
            known = rate == rate
            name = e(test.name).replace("/", "/<wbr>")  # a long path may break at its slashes
            parts.append(
                f"<tr><td>{name}</td><td class='n'>{_number(test.points)}</td>"
                f"<td class='w'>{'visible' if test.visibility == VISIBLE else 'hidden'}</td>"
                f"<td class='n'>{f'{rate:.0%}' if known else '-'}</td>"
                f"<td class='b'><span class='bar' style='width: {4 * rate if known else 0:.2f}em'>"
                "</span></td></tr>"
            )
        parts.append("</table></div>")
    mistakes = _mistakes(results, out)
    parts.append(f"<h2>Diagnosed mistakes ({len(mistakes)})</h2>")
    if not mistakes:
        parts.append("<p>The grader diagnosed no classic mistake in this class.</p>")
    else:
        parts.append(
            "<p>Ranked by how many students made them. A diagnosed mistake costs the test all "
            "its points.</p><div class='scroll'><table><tr><th>students</th><th>mistake</th>"
            "<th>example</th></tr>"
        )
    for mistake in mistakes:
        who = ", ".join(
            f"<a href='{_link(n)}'>{e(n)}</a>" for n in sorted(mistake["students"])
        )  # fmt: skip
        example = "no picture (array tests only)"
        if mistake["example"]:
            name, key, visible = mistake["example"]
            source = f"{'feedback' if visible else 'hidden'}/{_url(name)}/{quote(key)}.png"
            example = (
                f"<a href='{source}'><img class='example' src='{source}' "
                f"alt='{e(name)}, test {e(key)}'></a><br>{e(name)}, test {e(key)}"
            )
        parts.append(
            f"<tr><td class='n'>{len(mistake['students'])}</td><td>{e(mistake['says'])}"
            + (f"<br><small>made in {e(mistake['where'])}</small>" if mistake["where"] else "")
            + f"<br><small>tests {e(', '.join(sorted(mistake['tests'], key=_order)))}; {who}"
            "</small></td>"
            f"<td>{example}</td></tr>"
        )
    if mistakes:
        parts.append("</table></div>")
    partly = sorted(n for n in results if results[n].get("extra_data", {}).get(
        "modules_not_imported"))  # fmt: skip
    if broken or others or partly:
        count = len(broken) + len(others) + len(partly)
        parts.append(f"<h2>Not graded, or not all run ({count})</h2><ul>")
        for name in broken:
            error = results[name].get("extra_data", {}).get("does_not_import", "")
            parts.append(
                f"<li><a href='{_link(name)}'>{e(name)}</a>: raykit does not import, so no "
                f"test ran (0 points): <code>{e(error.splitlines()[0] if error else '')}</code>"
                f"{e(_where(error))}</li>"
            )
        parts += [
            f"<li><a href='{_link(name)}'>{e(name)}</a>: "
            f"{e(results[name]['extra_data']['modules_not_imported'])}</li>"
            for name in partly
        ]
        parts += [f"<li>{e(name)}: {e(rows[name]['status'])}</li>" for name in others]
        parts.append("</ul>")
    parts.append("<h2>Every student</h2><div class='scroll'><table>")
    parts.append("<tr><th>student</th><th>status</th><th>score</th></tr>")
    for name in sorted(rows, key=str.casefold):
        row = rows[name]
        shown = f"<a href='{_link(name)}'>{e(name)}</a>" if name in results else e(name)
        score = f"{_number(scores[name])} of {_number(total)}" if name in scores else ""
        parts.append(
            f"<tr><td>{shown}</td><td>{e(row['status'])}</td><td class='n'>{score}</td></tr>"
        )
    parts.append("</table></div>")
    return "\n".join(parts) + "\n"


def class_summary(rows: dict[str, dict]) -> str:
    """The class in one line, as the report and the batch command say it: ``9 submissions: 8
    graded, 1 whose raykit does not import (0 points); 1 entry is not a submission``."""
    statuses = [row["status"] for row in rows.values()]
    strays = sum(s.startswith(NOT_A_SUBMISSION) for s in statuses)
    graded, broken = statuses.count(GRADED), statuses.count(DOES_NOT_IMPORT)
    failed = len(statuses) - strays - graded - broken
    submissions = len(statuses) - strays
    return (
        f"{submissions} submission{'' if submissions == 1 else 's'}: {graded} graded"
        + (f", {broken} whose raykit does not import (0 points)" if broken else "")
        + (f", {failed} not graded (listed below)" if failed else "")
        + (f"; {strays} {'entry is' if strays == 1 else 'entries are'} not a submission"
           if strays else "")
    )  # fmt: skip

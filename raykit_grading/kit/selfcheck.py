"""Check your raykit before you submit it: the practice tests, judged as the grader judges.

    python check.py            (in the starter kit's folder)
    python check.py 3.6        (one test; ``python check.py 3``: stage 3's tests)

runs every practice test (or those named) in ``tests/expected/`` on your functions, with the
grader's own comparison: arrays within the stated tolerance, renders compared fairly at
silhouettes and against the classic mistakes (a render that shows one scores nothing for that
test, and the picture says which). It writes ``check/<test>.png`` for each render (yours |
expected | where they differ, captioned) and ``check/index.html`` with all of them; open that
in a browser.

The grader runs the same kinds of test on inputs it draws fresh each time, plus hidden tests:
passing here is a good sign, not the grade. (This file is copied into the starter kit from
``raykit_grading/kit/selfcheck.py``.)
"""

from __future__ import annotations

import json
import sys
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE / "tests")]

import numpy as np  # noqa: E402
from _grading.cases import read_case  # noqa: E402
from _grading.compare import (  # noqa: E402
    describe_inputs,
    feedback_page,
    judge_arrays,
    judge_image,
)
from _grading.tasks import TASKS  # noqa: E402
from PIL import Image  # noqa: E402

from raykit.io.images import quantize  # noqa: E402

EXPECTED = HERE / "tests" / "expected"


def _number(case: Path) -> tuple[int, ...]:
    return tuple(int(part) for part in case.name.split("_"))


def _said(case: Path) -> dict:
    """The case's classic mistakes: key -> (what it says, where it is made)."""
    path = case / "mistakes.json"
    said = json.loads(path.read_text()) if path.is_file() else {}
    return {
        key: (text, "") if isinstance(text, str) else (text["says"], text.get("where", ""))
        for key, text in said.items()
    }


def _arrays(path: Path, prefix: str = "") -> dict:
    with np.load(path) as data:
        return {k[len(prefix) :]: data[k] for k in data.files if k.startswith(prefix)}


def _run(task: str, spec: dict, arrays: dict) -> dict:
    return {k: np.asarray(v) for k, v in TASKS[task](spec, arrays).items()}


def _callees(case: Path, order: dict) -> list:
    """(name, what your function gives on the test's inputs or None, the reference's) for each
    function the test's function calls."""
    found = []
    for callee in order.get("callees", []):
        saved = case / "callees" / f"{callee['name']}.npz"
        try:
            mine = _run(callee["task"], callee["spec"], _arrays(saved, "in_"))
        except Exception:  # noqa: BLE001 - not written yet, or it failed: it differs
            mine = None
        found.append((callee["name"], mine, _arrays(saved, "out_")))
    return found


def run_case(case: Path, out: Path) -> dict:
    """One practice test, judged as the grader judges: its name, the share of its points,
    the points, what to say, and the picture file (renders) or None."""
    order, arrays, want = read_case(case)
    result = {"name": order["name"], "points": order.get("points", 1), "share": 0.0,
              "picture": None}  # fmt: skip
    try:
        got = _run(order["task"], order["spec"], arrays)
    except NotImplementedError as exc:
        return {**result, "message": f"not written yet: {exc}"}
    except Exception:  # noqa: BLE001 - whatever the student's code raised, say it
        last = traceback.format_exc().strip().splitlines()[-1]
        return {**result, "message": f"your code stopped with an error: {last}"}
    said = _said(case)
    if order["kind"] != "image":
        mistakes = [
            (text, _arrays(case / "mistakes" / f"{key}.npz"), where)
            for key, (text, where) in said.items()
        ]
        spec = {k: v for k, v in order["spec"].items() if k != "folder"}
        verdict = judge_arrays(got, want, spec=spec, arrays=arrays, mistakes=mistakes,
                               callees=_callees(case, order), caller=order["task"])  # fmt: skip
        return {**result, "share": verdict.share, "message": verdict.message}
    mine, reference = quantize(got["rgb"]), quantize(want["rgb"])
    if mine.shape != reference.shape:
        return {**result, "message": f"shape {mine.shape}, expected {reference.shape}"}
    mistakes = (
        (text, np.asarray(Image.open(case / "mistakes" / f"{key}.png").convert("RGB")), where)
        for key, (text, where) in said.items()
    )
    spec = {k: v for k, v in order["spec"].items() if k != "folder"}
    verdict = judge_image(mine, reference, mistakes, inputs=describe_inputs(spec, arrays))
    picture = out / f"{case.name}.png"
    Image.fromarray(verdict.picture).save(picture)
    return {**result, "share": verdict.share, "message": verdict.message, "picture": picture.name}


def _points(value: float) -> str:
    return f"{value:.4g}"


def page(rows: list[dict]) -> str:
    """The self-check page (:func:`feedback_page`, as a batch writes each student's)."""
    return feedback_page(rows)


def _chosen(cases: list[Path], wanted: list[str], parser) -> list[Path]:
    """The cases a student asked for: a test's number (``3.6``) or a stage's (``3``)."""
    if not wanted:
        return cases
    numbers = {".".join(map(str, _number(case))): case for case in cases}
    chosen = []
    for text in wanted:
        found = [c for n, c in numbers.items() if n == text or n.split(".")[0] == text]
        if not found:
            parser.error(f"no practice test {text}: they are {', '.join(numbers)}")
        chosen += [c for c in found if c not in chosen]
    return sorted(chosen, key=_number)


def main(argv: list[str] | None = None) -> int:
    import argparse

    parser = argparse.ArgumentParser(
        prog="python check.py",
        description=__doc__.split("\n\n", 1)[0],
        epilog="Examples: python check.py (every practice test); python check.py 3.6 (test "
        "3.6 only); python check.py 1 2 (stages 1 and 2). The page is check/index.html.",
    )
    parser.add_argument(
        "tests",
        nargs="*",
        metavar="TEST",
        help="a test's number (3.6) or a stage's (3); default: every practice test",
    )
    args = parser.parse_args(argv)
    cases = sorted((p for p in EXPECTED.iterdir() if p.is_dir()), key=_number)
    cases = _chosen(cases, args.tests, parser)
    out = HERE / "check"
    out.mkdir(exist_ok=True)
    rows = []
    for case in cases:
        row = run_case(case, out)
        rows.append(row)
        passed = row["share"] >= 1.0
        first, *more = row["message"].splitlines()
        print(f"{'pass' if passed else 'FAIL'}  {row['name']}: {first}")
        for line in more if not passed else []:
            print(f"      {line}")
    (out / "index.html").write_text(page(rows))
    passed = sum(row["share"] >= 1.0 for row in rows)
    earned = sum(r["share"] * r["points"] for r in rows)
    print(
        f"{passed} of {len(rows)} practice tests pass ({_points(earned)} of "
        f"{_points(sum(r['points'] for r in rows))} points); the page: {out / 'index.html'}"
    )
    return 0 if passed == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())

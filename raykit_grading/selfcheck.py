"""Check your raykit before you submit it: the practice tests, judged as the grader judges.

    python check.py            (in the starter kit's folder)

runs every practice test in ``tests/expected/`` on your functions, with the grader's own
comparison: arrays within the stated tolerance, renders compared fairly at silhouettes and
against the classic mistakes (a render that shows one scores nothing for that test, and the
picture says which). It writes ``check/<test>.png`` for each render (yours | expected | where
they differ, captioned) and ``check/index.html`` with all of them; open that in a browser.

The grader runs the same kinds of test on inputs it draws fresh each time, plus hidden tests:
passing here is a good sign, not the grade. (This file is copied into the starter kit from
``raykit_grading/selfcheck.py``.)
"""

from __future__ import annotations

import html
import json
import sys
import traceback
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE / "tests")]

import numpy as np  # noqa: E402
from _grading.cases import read_case  # noqa: E402
from _grading.child import TASKS  # noqa: E402
from _grading.compare import check_arrays, judge_image  # noqa: E402
from PIL import Image  # noqa: E402

from raykit.io.images import quantize  # noqa: E402

EXPECTED = HERE / "tests" / "expected"


def _number(case: Path) -> tuple[int, ...]:
    return tuple(int(part) for part in case.name.split("_"))


def run_case(case: Path, out: Path) -> tuple[str, bool, str, str | None]:
    """(test name, passed, what to say, picture file or None) for one practice test."""
    order, arrays, want = read_case(case)
    try:
        got = {k: np.asarray(v) for k, v in TASKS[order["task"]](order["spec"], arrays).items()}
    except NotImplementedError as exc:
        return order["name"], False, f"not written yet: {exc}", None
    except Exception:  # noqa: BLE001 - whatever the student's code raised, say it
        last = traceback.format_exc().strip().splitlines()[-1]
        return order["name"], False, f"your code stopped with an error: {last}", None
    if order["kind"] != "image":
        passed, message = check_arrays(got, want)
        return order["name"], passed, message, None
    mine, reference = quantize(got["rgb"]), quantize(want["rgb"])
    if mine.shape != reference.shape:
        return order["name"], False, f"shape {mine.shape}, expected {reference.shape}", None
    says = (
        json.loads((case / "mistakes.json").read_text())
        if (case / "mistakes.json").is_file()
        else {}
    )
    mistakes = (
        (text, np.asarray(Image.open(case / "mistakes" / f"{key}.png").convert("RGB")))
        for key, text in says.items()
    )
    verdict = judge_image(mine, reference, mistakes)
    picture = out / f"{case.name}.png"
    Image.fromarray(verdict.picture).save(picture)
    return order["name"], verdict.share >= 1.0, verdict.message, picture.name


def main() -> int:
    out = HERE / "check"
    out.mkdir(exist_ok=True)
    rows = []
    for case in sorted((p for p in EXPECTED.iterdir() if p.is_dir()), key=_number):
        name, passed, message, picture = run_case(case, out)
        rows.append((name, passed, message, picture))
        first, *more = message.splitlines()
        print(f"{'pass' if passed else 'FAIL'}  {name}: {first}")
        for line in more if not passed else []:
            print(f"      {line}")
    page = ["<!doctype html><meta charset='utf-8'><title>raykit: self-check</title>",
            "<h1>raykit: your practice tests</h1>"]  # fmt: skip
    for name, passed, message, picture in rows:
        colour = "green" if passed else "crimson"
        page.append(f"<h2 style='color:{colour}'>{'pass' if passed else 'FAIL'}: "
                    f"{html.escape(name)}</h2><pre>{html.escape(message)}</pre>")  # fmt: skip
        if picture:
            page.append(f"<img src='{picture}' alt='yours | expected | where they differ'>")
    (out / "index.html").write_text("\n".join(page) + "\n")
    passed = sum(row[1] for row in rows)
    print(f"{passed} of {len(rows)} practice tests pass; pictures: {out / 'index.html'}")
    return 0 if passed == len(rows) else 1


if __name__ == "__main__":
    sys.exit(main())

"""Comparing a submission's results with the reference: arrays within a tolerance, and images
fairly at silhouettes.

Arrays (:func:`check_arrays`): the same shape, numbers, and equal within rtol 1e-6, atol 1e-9;
a miss may be NaN or inf on either side.

Images (:func:`compare_images`):
A pixel *matches* when each of its channels is within ``tolerance`` (8-bit levels) of the
reference pixel, or of one of that pixel's 3x3 neighbours: an edge pixel that rounding put on
the other side of a silhouette costs nothing, a wrong colour or a shifted object does. The
score follows the matched fraction: full at ``full_at`` (99.5%) and above, none below
``none_below`` (90%), linear between. PSNR is reported beside it.
"""

from __future__ import annotations

import html
import itertools
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

DIAGNOSE_FROM = 0.95  # a mistake is named only if it explains this much of the image
STRICTLY_RIGHT = 0.99  # an image this close to the reference, pixel for pixel, needs no diagnosis


@dataclass(frozen=True)
class Scoring:
    tolerance: int = 2
    full_at: float = 0.995
    none_below: float = 0.90


DEFAULT_SCORING = Scoring()


@dataclass(frozen=True)
class Comparison:
    matched: np.ndarray  # (H, W) bool
    fraction: float
    psnr: float

    def score(self, scoring: Scoring = DEFAULT_SCORING) -> float:
        """The share of an image's points earned, in [0, 1]."""
        span = scoring.full_at - scoring.none_below
        return float(np.clip((self.fraction - scoring.none_below) / span, 0.0, 1.0))


def compare_images(
    student: np.ndarray, reference: np.ndarray, scoring: Scoring = DEFAULT_SCORING
) -> Comparison:
    """Compare two uint8 images ``(H, W, 3)`` of the same shape."""
    student = student.astype(np.int16)
    reference = reference.astype(np.int16)
    height, width = reference.shape[:2]
    padded = np.pad(reference, ((1, 1), (1, 1), (0, 0)), mode="edge")
    matched = np.zeros((height, width), dtype=bool)
    for dy in range(3):
        for dx in range(3):
            neighbour = padded[dy : dy + height, dx : dx + width]
            matched |= (np.abs(student - neighbour) <= scoring.tolerance).all(axis=-1)
    mse = float(np.mean((student.astype(float) - reference) ** 2))
    psnr = float("inf") if mse == 0 else 10 * np.log10(255.0**2 / mse)
    return Comparison(matched, float(matched.mean()), psnr)


def strict_matched(student: np.ndarray, reference: np.ndarray, tolerance: int = 2) -> np.ndarray:
    """``(H, W)``: pixels within ``tolerance`` of the reference pixel itself (no neighbours)."""
    difference = np.abs(student.astype(np.int16) - reference.astype(np.int16))
    return (difference <= tolerance).all(axis=-1)


def strict_fraction(student: np.ndarray, reference: np.ndarray, tolerance: int = 2) -> float:
    """The share of pixels within ``tolerance`` of the reference pixel itself (no neighbours):
    for telling apart images that the fair comparison cannot, such as a half-pixel shift."""
    return float(strict_matched(student, reference, tolerance).mean())


def diagnose(
    mine: np.ndarray, want: np.ndarray, mistakes: Iterable[tuple]
) -> tuple[str, float, float, str] | None:
    """The classic mistake whose picture explains ``mine`` better than ``want`` does, pixel
    for pixel (strictly, so that even a half-pixel shift shows): (what it says, the share of
    pixels it explains, the share the reference explains, where it is made), or None.
    ``mistakes`` yields (what it says, its picture[, where it is made]) and is only looked at
    when ``mine`` is not right; a mistake that does not change this picture is skipped, and on
    a tie the one listed first wins (the catalog's mistakes come before the one-pixel
    shifts)."""
    right = strict_fraction(mine, want)
    if right >= STRICTLY_RIGHT:
        return None
    best, best_fraction = None, max(right, DIAGNOSE_FROM)
    for says, wrong, *where in mistakes:
        if wrong.shape != mine.shape or strict_fraction(wrong, want) >= 1.0:
            continue
        matched = strict_fraction(mine, wrong)
        if matched > best_fraction:
            best, best_fraction = (says, where[0] if where else ""), matched
    return None if best is None else (best[0], best_fraction, right, best[1])


@dataclass(frozen=True)
class Verdict:
    """How a test fares: the share of its points, what to tell the student, the picture (for
    renders; None for arrays)."""

    share: float
    message: str
    picture: np.ndarray | None = None
    diagnosed: tuple[str, str] | None = None  # the classic mistake named: (says, where)


ImageVerdict = Verdict


def judge_image(
    mine: np.ndarray,
    want: np.ndarray,
    mistakes: Iterable[tuple] = (),
    scoring: Scoring = DEFAULT_SCORING,
    inputs: str = "",
) -> Verdict:
    """Compare a uint8 render with the reference, name a classic mistake it shows (which
    then costs all of the test's points: it is systematic, not float noise), and draw the
    captioned feedback picture. Every percentage in the message is one the score comes from.
    The grader and the students' self-check both use this."""
    result = compare_images(mine, want, scoring)
    share = result.score(scoring)
    mistake = diagnose(mine, want, itertools.chain(mistakes, shifted_by_one(want)))
    if mistake is None:
        lines = [
            f"{result.fraction:.2%} of pixels match the reference, so this test gives "
            f"{share:.0%} of its points (all from {scoring.full_at:.1%}, none below "
            f"{scoring.none_below:.0%}; a pixel matches when it is within "
            f"{scoring.tolerance} levels of the reference pixel or one of its 8 neighbours). "
            f"PSNR {result.psnr:.1f} dB."
        ]
        picture = feedback_picture(mine, want, result.matched)
    else:
        says, fraction, right, where = mistake
        share = 0.0
        lines = [
            f"Diagnosis: your image is what the renderer gives when {says}"
            + (f" (made in {where})" if where else "")
            + ".",
            f"Pixel for pixel, your image equals that mistake's picture in {fraction:.1%} of "
            f"pixels and the right picture in only {right:.1%}. That is a systematic mistake, "
            "not rounding, so this test gives 0% of its points, however close the picture "
            "looks.",
        ]
        note = f"Diagnosed: {says} (red: every pixel that differs)"
        picture = feedback_picture(mine, want, strict_matched(mine, want), note)
    if inputs:
        lines.append(f"Inputs: {inputs}")
    named = None if mistake is None else (mistake[0], mistake[3])
    return Verdict(share, "\n".join(lines), picture, named)


SHIFTS = {"down": (1, 0), "up": (-1, 0), "right": (0, 1), "left": (0, -1)}


def shifted_by_one(image: np.ndarray):
    """(what it says, picture) for ``image`` moved by one pixel each way, edges repeated: an
    off-by-one in the pixel indices, which the fair comparison's 3x3 neighbourhood would
    otherwise forgive."""
    height, width = image.shape[:2]
    padded = np.pad(image, ((1, 1), (1, 1), (0, 0)), mode="edge")
    for way, (dy, dx) in SHIFTS.items():
        moved = padded[1 - dy : 1 - dy + height, 1 - dx : 1 - dx + width]
        yield (
            f"the picture is shifted by one pixel ({way}): an off-by-one in the pixel indices",
            moved,
            "the pixel indices (a row or column counted from 1, or one too many)",
        )


CAPTIONS = ("yours", "expected", "where they differ (red)")
PANEL_WIDTH = 240  # pixels a small picture's panel is scaled up to, at least
PANEL_HEIGHT = 480  # ... unless it would be taller than this
STRIP_HEIGHT = 40  # a line-scan strip (a row or a few) is drawn at least this tall


def picture_scale(height: int, width: int) -> tuple[int, int]:
    """(across, down): how many times each pixel of a ``height x width`` picture is repeated
    (nearest neighbour) so that one pixel can be seen: the same both ways, up to
    ``PANEL_WIDTH`` wide and ``PANEL_HEIGHT`` tall; a scan's strip of a row or a few is drawn
    taller still, ``STRIP_HEIGHT`` at least."""
    across = max(1, min(-(-PANEL_WIDTH // width), PANEL_HEIGHT // height))
    down = max(across, -(-STRIP_HEIGHT // height))
    return across, down


def feedback_picture(
    student: np.ndarray, reference: np.ndarray, matched: np.ndarray, note: str | None = None
) -> np.ndarray:
    """Yours | expected | mismatches in red over a greyed reference, side by side, each panel
    captioned, and ``note`` (e.g. the diagnosed mistake) on a line above them; uint8."""
    import textwrap

    from PIL import Image, ImageDraw, ImageFont

    grey = reference.mean(axis=-1, keepdims=True)
    greyed = np.repeat(0.35 * grey + 0.65 * 255, 3, axis=-1)
    greyed[~matched] = [230, 20, 20]
    across, down = picture_scale(*reference.shape[:2])
    student, reference, greyed = (
        np.kron(np.asarray(a), np.ones((down, across, 1))) for a in (student, reference, greyed)
    )
    height, width = reference.shape[:2]
    gap, line = 6, 18
    total = 3 * width + 2 * gap
    notes = textwrap.wrap(note, max(20, total // 7)) if note else []
    top = line * (len(notes) + 1) + 4
    canvas = Image.new("RGB", (total, height + top), "white")
    draw = ImageDraw.Draw(canvas)
    font = ImageFont.load_default(13)
    for row, text in enumerate(notes):
        draw.text((2, 2 + row * line), text, fill=(150, 0, 0), font=font)
    for i, (panel, caption) in enumerate(zip((student, reference, greyed), CAPTIONS, strict=True)):
        left = i * (width + gap)
        canvas.paste(Image.fromarray(np.asarray(panel, np.uint8)), (left, top))
        draw.text((left + 2, top - line), caption, fill=(0, 0, 0), font=font)
    return np.asarray(canvas)


RTOL, ATOL = 1e-6, 1e-9
SHOWN_DIFFERENCES = 3  # the first few differences a message lists
SMALL_INPUT = 12  # numbers: an input this small is shown in full
DIAGNOSE_ARRAYS_FROM = 0.8  # a mistake is named if it explains this share of the disputed values


def _number(value) -> str:
    """A number as a person writes it: ``-0.888888889``, ``3``, ``inf``, ``True``; no numpy
    repr."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    value = float(value)
    if not np.isfinite(value):
        return str(value)
    if value == int(value) and abs(value) < 1e15:
        return str(int(value))
    return f"{value:.10g}"


def _numbers(values) -> str:
    values = np.asarray(values)
    if values.ndim == 0:
        return _number(values[()])
    return "[" + ", ".join(_numbers(v) for v in values) + "]"


def _differing(value: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Where two arrays of one shape differ beyond the tolerance; a miss (NaN or inf) matches
    a miss."""
    value, reference = value.astype(float), reference.astype(float)
    miss_got, miss_want = ~np.isfinite(value), ~np.isfinite(reference)
    wrong = miss_got != miss_want
    both = ~miss_got & ~miss_want
    wrong[both] |= ~np.isclose(value[both], reference[both], rtol=RTOL, atol=ATOL)
    return wrong


def _problem(got: dict, want: dict) -> str | None:
    """What makes ``got`` not even comparable with ``want`` (a result missing, another shape,
    not numbers), or None."""
    for key, reference in want.items():
        if key not in got:
            return f"no result named {key!r}"
        value = got[key]
        if value.shape != reference.shape:
            return f"{key}: shape {value.shape}, expected {reference.shape}"
        if not (np.issubdtype(value.dtype, np.number) or value.dtype == bool):
            return f"{key}: values of type {value.dtype}, expected numbers"
    return None


def _agree(got: dict, want: dict) -> bool:
    return _problem(got, want) is None and not any(_differing(got[k], want[k]).any() for k in want)


def check_arrays(got: dict[str, np.ndarray], want: dict[str, np.ndarray]) -> tuple[bool, str]:
    """Every expected array present, of the same shape, numeric, and equal within tolerance;
    (passed, what to say: the first differences, as plain numbers).

    A miss may be NaN or inf in either; integers must be equal exactly.
    """
    verdict = judge_arrays(got, want)
    return verdict.share >= 1.0, verdict.message


def describe_inputs(spec: dict, arrays: dict[str, np.ndarray]) -> str:
    """The inputs of a test, for a person: the spec's settings, and each array in full when it
    is small (its shape otherwise; the rows at a difference are shown beside it)."""
    parts = []
    for key, value in spec.items():
        if key == "folder":
            continue
        if key == "scene" and isinstance(value, dict):
            camera = value.get("camera", {})
            objects = sum(len(v) for v in value.values() if isinstance(v, list))
            parts.append(f"a scene of {objects} objects seen by the camera {_settings(camera)}")
        elif isinstance(value, dict):
            parts.append(f"{key}: {_settings(value)}")
        else:
            parts.append(f"{key} = {_settings(value)}")
    for key, value in arrays.items():
        value = np.asarray(value)
        if value.size <= SMALL_INPUT:
            parts.append(f"{key} = {_numbers(value)}")
        else:
            parts.append(f"{key}: {' x '.join(map(str, value.shape))} numbers")
    return "; ".join(parts)


def _settings(value) -> str:
    if isinstance(value, dict):
        return "(" + ", ".join(f"{k} = {_settings(v)}" for k, v in value.items()) + ")"
    if isinstance(value, (list, tuple, np.ndarray)) and np.asarray(value).dtype.kind in "fiub":
        return _numbers(value)
    if isinstance(value, (int, float, np.number)) and not isinstance(value, bool):
        return _number(value)
    return str(value)


def _pattern(value: np.ndarray, reference: np.ndarray, wrong: np.ndarray) -> str:
    """A plain pattern in the differences: every wrong value off by the same amount, or by the
    same factor, or the right values in another order (rows reversed)."""
    value, reference = value.astype(float)[wrong], reference.astype(float)[wrong]
    if not (np.isfinite(value).all() and np.isfinite(reference).all()) or value.size < 2:
        return ""
    offset = value - reference
    if np.allclose(offset, offset[0], rtol=1e-6, atol=1e-12):
        return f"every differing value is off by the same amount, {_number(offset[0])}"
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = value / reference
    if np.isfinite(ratio).all() and np.allclose(ratio, ratio[0], rtol=1e-6):
        return f"every differing value is {_number(ratio[0])} times the expected one"
    return ""


def judge_arrays(
    got: dict[str, np.ndarray],
    want: dict[str, np.ndarray],
    *,
    spec: dict | None = None,
    arrays: dict[str, np.ndarray] | None = None,
    tolerance: str = f"each number within rtol {RTOL:g}, atol {ATOL:g}",
    mistakes: Iterable[tuple[str, dict, str]] = (),
    callees: Iterable[tuple[str, dict | None, dict]] = (),
    caller: str = "",
    hidden: bool = False,
) -> Verdict:
    """An array test's verdict: all points if every expected array matches within the
    tolerance, none otherwise, and what to tell the student.

    A failing test's message gives the first few differences as plain numbers with the input
    rows they come from and the inputs (small ones in full), a pattern in the differences,
    the classic mistake that explains them (``mistakes``: (what it says, the results the
    mistake gives, where it is made)), and for a function that calls other student functions
    (``callees``: (name, what the student's gave on the same inputs or None, the reference)),
    which of them the difference starts in. ``hidden``: the message carries only the grader's
    own words (no values, shapes or inputs: nothing the submission chose).
    """
    problem = _problem(got, want)
    if problem is None and not any(_differing(got[k], want[k]).any() for k in want):
        return Verdict(1.0, f"all values match ({tolerance})")
    lines = []
    if problem is not None:
        key = next(k for k in want if _problem({k: got[k]} if k in got else {}, {k: want[k]}))
        lines.append(
            f"{key}: not the result expected (a hidden test: what was returned is not shown)"
            if hidden and key in got
            else problem
        )
    else:
        for key, reference in want.items():
            value = got[key]
            wrong = _differing(value, reference)
            if not wrong.any():
                continue
            if hidden:
                lines.append(f"{key}: your values differ from the reference ({tolerance})")
                continue
            lines.append(
                f"{key}: {int(wrong.sum())} of {wrong.size} values differ from the reference "
                f"({tolerance}). The first differences:"
            )
            lines += _first_differences(key, value, reference, wrong, arrays or {})
            pattern = _pattern(value, reference, wrong)
            if pattern:
                lines.append(f"  ({pattern})")
    if spec is not None or arrays:
        if hidden:
            lines.append("Inputs: not shown (a hidden test)")
        else:
            lines.append(f"Inputs: {describe_inputs(spec or {}, arrays or {})}")
    named = None
    if problem is None:
        named = _diagnose_arrays(got, want, mistakes)
        if named is not None:
            says, explained, where = named
            lines.append(
                f"Diagnosis: your results are what the code gives when {says}"
                + (f" (made in {where})" if where else "")
                + (f"; it explains {explained:.0%} of the values that differ." if not hidden
                   else ".")
            )  # fmt: skip
    lines += _callee_lines(list(callees), caller)
    return Verdict(0.0, "\n".join(lines), diagnosed=None if named is None else (named[0], named[2]))


def _first_differences(key, value, reference, wrong, arrays) -> list[str]:
    """The first differences, one line each (a whole row of a (N, k) result), with the input
    rows of the same index."""
    lines = []
    rows = np.unique(np.argwhere(wrong)[:, 0]) if value.ndim > 1 else np.flatnonzero(wrong)
    for row in rows[:SHOWN_DIFFERENCES]:
        row = int(row)
        lines.append(
            f"  {key}[{row}]: yours {_numbers(value[row])}, expected {_numbers(reference[row])}"
        )
        beside = [
            f"{name}[{row}] = {_numbers(np.asarray(a)[row])}"
            for name, a in arrays.items()
            if np.ndim(a) >= 1 and len(a) == len(value) and np.size(a) > SMALL_INPUT
        ]
        if beside:
            lines.append(f"    for {', '.join(beside)}")
    if len(rows) > SHOWN_DIFFERENCES:
        lines.append(f"  … and {len(rows) - SHOWN_DIFFERENCES} more")
    return lines


def _diagnose_arrays(got, want, mistakes) -> tuple[str, float, str] | None:
    """The mistake that explains the differences best: of the values where the submission or
    the mistake differs from the reference, the share where the submission equals the
    mistake; named from ``DIAGNOSE_ARRAYS_FROM``. A mistake that changes nothing here, or
    cannot be compared, is skipped; on a tie the first listed wins."""
    best, best_share = None, DIAGNOSE_ARRAYS_FROM - 1e-12
    for says, results, where in mistakes:
        if _problem(results, want) is not None:
            continue
        disputed = agreed = 0
        for key, reference in want.items():
            mine_off = _differing(got[key], reference)
            theirs_off = _differing(results[key], reference)
            same = ~_differing(got[key], results[key])
            disputed += int((mine_off | theirs_off).sum())
            agreed += int(((mine_off | theirs_off) & same).sum())
        if disputed == 0 or not any(_differing(results[k], want[k]).any() for k in want):
            continue
        share = agreed / disputed
        if share > best_share:
            best, best_share = (says, share, where), share
    return best


def _callee_lines(callees: list, caller: str) -> list[str]:
    """Which of the functions a test's function calls the difference starts in."""
    if not callees:
        return []
    names = [name for name, _, _ in callees]
    them = names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]
    first = next((n for n, mine, want in callees if mine is None or not _agree(mine, want)), None)
    if first is None:
        return [
            f"{caller or 'This function'} calls {them}; on this test's inputs "
            f"{'it gives' if len(names) == 1 else 'they give'} the right results, so the "
            f"difference starts in {caller or 'the function tested'} itself."
        ]
    return [
        f"{caller or 'This function'} calls {them}; on this test's inputs {first} already "
        f"gives other results than the reference's, so the difference starts in {first}."
    ]


def feedback_html(message: str, picture: str | None = None) -> str:
    """One failure (or pass) as HTML, the same on Gradescope and on the self-check page: the
    message wrapped at any width, and the picture (a URL: a file or a data: URI) scaled to
    the width available, pixels kept sharp."""
    parts = [
        '<pre style="white-space: pre-wrap; overflow-wrap: anywhere; margin: 0.4em 0; '
        'font-size: 0.9em">' + html.escape(message) + "</pre>"
    ]
    if picture is not None:
        parts.append(
            f'<img src="{html.escape(picture)}" alt="{" | ".join(CAPTIONS)}" '
            'style="max-width: 100%; height: auto; image-rendering: pixelated">'
        )
    return "\n".join(parts)


PAGE_STYLE = """
body { font-family: system-ui, sans-serif; line-height: 1.4; max-width: 72em;
       margin: 0 auto; padding: 0.5em 1em; overflow-wrap: anywhere; }
.summary { font-size: 1.2em; padding: 0.6em 0.8em; border-radius: 6px; background: #f3f3f3; }
section { border-top: 1px solid #ccc; padding: 0.3em 0 0.8em; }
h3 { margin: 0.4em 0 0.2em; font-size: 1.05em; }
.fail h3 { color: #a4001d; } .pass { color: #1f6b32; }
"""
PRACTICE_NOTE = (
    "The grader runs the same kinds of test on inputs it draws itself, plus hidden tests: "
    "passing here is a good sign, not the grade."
)


def _points(value: float) -> str:
    return f"{value:.4g}"


def feedback_page(
    rows: list[dict],
    *,
    heading: str = "raykit: your practice tests",
    tests: str = "practice tests",
    note: str = PRACTICE_NOTE,
    top: str = "",
) -> str:
    """The feedback page, the same for the self-check (``check.py``) and for each student of
    a batch: the summary first, then the failing tests (each with its message, inputs and
    picture), then the passing ones; it wraps at any width. ``rows``: each test's ``name``,
    ``points``, ``share`` of them earned, ``message`` and ``picture`` (a URL or None);
    ``top``: text said once above the tests (e.g. why none of them ran)."""
    passed = [r for r in rows if r["share"] >= 1.0]
    failing = [r for r in rows if r["share"] < 1.0]
    earned = sum(r["share"] * r["points"] for r in rows)
    total = sum(r["points"] for r in rows)
    parts = [
        "<!doctype html><html lang='en'><meta charset='utf-8'>",
        "<meta name='viewport' content='width=device-width, initial-scale=1'>",
        f"<title>{html.escape(heading)}: {len(passed)} of {len(rows)} pass</title>",
        f"<style>{PAGE_STYLE}</style>",
        f"<h1>{html.escape(heading)}</h1>",
        f"<p class='summary'><strong>{len(passed)} of {len(rows)} {tests} pass: "
        f"{_points(earned)} of {_points(total)} points.</strong> "
        + ("Failing tests first." if failing else f"Every one of the {tests} passes.")
        + (f" {html.escape(note)}" if note else "")
        + "</p>",
    ]
    if top:
        parts.append(feedback_html(top))
    if failing:
        parts.append(f"<h2>Failing ({len(failing)})</h2>")
    for row in failing:
        parts.append(
            f"<section class='fail'><h3>FAIL: {html.escape(row['name'])}: "
            f"{_points(row['share'] * row['points'])} of {_points(row['points'])} points</h3>"
            + feedback_html(row["message"], row["picture"])
            + "</section>"
        )
    if passed:
        parts.append(f"<h2>Passing ({len(passed)})</h2><ul>")
        parts += [
            f"<li class='pass'>pass: {html.escape(r['name'])}: {_points(r['points'])} of "
            f"{_points(r['points'])} points"
            + (f" (<a href='{html.escape(r['picture'])}'>the picture</a>)" if r["picture"] else "")
            + "</li>"
            for r in passed
        ]
        parts.append("</ul>")
    return "\n".join(parts) + "\n"

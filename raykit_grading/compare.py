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
    mine: np.ndarray, want: np.ndarray, mistakes: Iterable[tuple[str, np.ndarray]]
) -> tuple[str, float] | None:
    """The classic mistake whose picture explains ``mine`` better than ``want`` does, pixel
    for pixel (strictly, so that even a half-pixel shift shows): (what it says, the share of
    pixels it explains), or None. ``mistakes`` yields (what it says, its picture) and is only
    looked at when ``mine`` is not right; a mistake that does not change this picture is
    skipped."""
    best, best_fraction = None, max(strict_fraction(mine, want), DIAGNOSE_FROM)
    if best_fraction >= STRICTLY_RIGHT:
        return None
    for says, wrong in mistakes:
        if wrong.shape != mine.shape or strict_fraction(wrong, want) >= 1.0:
            continue
        matched = strict_fraction(mine, wrong)
        if matched > best_fraction:
            best, best_fraction = says, matched
    return None if best is None else (best, best_fraction)


@dataclass(frozen=True)
class ImageVerdict:
    """How a render fares: the share of its points, what to tell the student, the picture."""

    share: float
    message: str
    picture: np.ndarray


def judge_image(
    mine: np.ndarray,
    want: np.ndarray,
    mistakes: Iterable[tuple[str, np.ndarray]] = (),
    scoring: Scoring = DEFAULT_SCORING,
) -> ImageVerdict:
    """Compare a uint8 render with the reference, name a classic mistake it shows (which
    then costs all of the test's points: it is systematic, not float noise), and draw the
    captioned feedback picture. The grader and the students' self-check both use this."""
    result = compare_images(mine, want, scoring)
    share = result.score(scoring)
    mistakes = itertools.chain(mistakes, shifted_by_one(want))
    lines = [
        f"{result.fraction:.2%} of pixels match the reference (full marks from "
        f"{scoring.full_at:.1%}, none below {scoring.none_below:.0%}); "
        f"PSNR {result.psnr:.1f} dB"
    ]
    mistake = diagnose(mine, want, mistakes)
    if mistake is None:
        picture = feedback_picture(mine, want, result.matched)
    else:
        says, fraction = mistake
        lines.append(
            f"Your image matches what the renderer gives when {says} ({fraction:.1%} of "
            "pixels exactly). That is a systematic mistake, not rounding: this test gives no "
            "points for it, however close the picture looks."
        )
        share = 0.0
        note = f"Diagnosed: {says} (red: every pixel it changes)"
        picture = feedback_picture(mine, want, strict_matched(mine, want), note)
    return ImageVerdict(share, "\n".join(lines), picture)


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
        )


CAPTIONS = ("yours", "expected", "where they differ (red)")


def feedback_picture(
    student: np.ndarray, reference: np.ndarray, matched: np.ndarray, note: str | None = None
) -> np.ndarray:
    """Yours | expected | mismatches in red over a greyed reference, side by side, each panel
    captioned, and ``note`` (e.g. the diagnosed mistake) on a line above them; uint8."""
    from PIL import Image, ImageDraw, ImageFont

    grey = reference.mean(axis=-1, keepdims=True)
    greyed = np.repeat(0.35 * grey + 0.65 * 255, 3, axis=-1)
    greyed[~matched] = [230, 20, 20]
    scale = max(1, -(-200 // reference.shape[1]))  # small images (a scan's strip) made visible
    student, reference, greyed = (
        np.kron(np.asarray(a), np.ones((scale, scale, 1))) for a in (student, reference, greyed)
    )
    height, width = reference.shape[:2]
    gap, line = 6, 18
    top = line * (2 if note else 1) + 4
    canvas = Image.new("RGB", (3 * width + 2 * gap, height + top), "white")
    draw = ImageDraw.Draw(canvas)
    font = ImageFont.load_default(13)
    if note:
        draw.text((2, 2), note, fill=(150, 0, 0), font=font)
    for i, (panel, caption) in enumerate(zip((student, reference, greyed), CAPTIONS, strict=True)):
        left = i * (width + gap)
        canvas.paste(Image.fromarray(np.asarray(panel, np.uint8)), (left, top))
        draw.text((left + 2, top - line), caption, fill=(0, 0, 0), font=font)
    return np.asarray(canvas)


def check_arrays(got: dict[str, np.ndarray], want: dict[str, np.ndarray]) -> tuple[bool, str]:
    """Every expected array present, of the same shape, numeric, and equal within tolerance.

    A miss may be NaN or inf in either; integers must be equal exactly.
    """
    for key, reference in want.items():
        if key not in got:
            return False, f"no result named {key!r}"
        value = got[key]
        if value.shape != reference.shape:
            return False, f"{key}: shape {value.shape}, expected {reference.shape}"
        if not (np.issubdtype(value.dtype, np.number) or value.dtype == bool):
            return False, f"{key}: values of type {value.dtype}, expected numbers"
        value = value.astype(float)
        reference = reference.astype(float)
        miss_got, miss_want = ~np.isfinite(value), ~np.isfinite(reference)
        wrong = miss_got != miss_want
        both = ~miss_got & ~miss_want
        wrong[both] |= ~np.isclose(value[both], reference[both], rtol=1e-6, atol=1e-9)
        if wrong.any():
            first = np.argwhere(wrong)[0]
            where = tuple(int(i) for i in first)
            return False, (
                f"{key}: {int(wrong.sum())} of {wrong.size} values differ; first at "
                f"{where}: got {value[where]!r}, expected {reference[where]!r}"
            )
    return True, "all values match"

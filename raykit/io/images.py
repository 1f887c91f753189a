"""Images out: quantising float colours to 8 bits and writing files without half-written results.

Quantising follows the scene format: value = floor(clamp(c, 0, 1)·255 + 0.5), so halves round up
(0.3 -> 77), unlike numpy's round-half-to-even.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

import numpy as np
from PIL import Image


def quantize(rgb: np.ndarray) -> np.ndarray:
    """Float colours ``(..., 3)`` in [0, 1] to uint8, halves rounding up."""
    return np.floor(np.clip(rgb, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def save_image(pixels: np.ndarray, path: str | Path) -> None:
    """Write ``pixels`` (float in [0, 1] or uint8, ``(H, W, 3)`` or ``(H, W)``) to ``path``.

    The format follows the file's suffix (``.png`` and anything else Pillow writes). The image is
    written to a temporary file beside ``path`` and renamed over it, so ``path`` is either the
    whole new image or untouched. Raises ``OSError`` or ``ValueError`` (unknown suffix).
    """
    path = Path(path)
    image_format = _image_format_of(path)
    if pixels.dtype != np.uint8:
        pixels = quantize(pixels)
    _write_whole(path, lambda stream: Image.fromarray(pixels).save(stream, format=image_format))


def check_image_path(path: str | Path) -> None:
    """Raise ``ValueError`` now, before any work, if :func:`save_image` could not write
    ``path``: its folder is missing, not a folder or not writable, ``path`` is a folder, or
    Pillow writes no format with its suffix. The message names ``path`` as the user gave it."""
    path = Path(path)
    _check_folder(path)
    _image_format_of(path)


def check_figure_path(path: str | Path) -> None:
    """The same checks as :func:`check_image_path`, for a matplotlib figure (:func:`save_figure`):
    the suffix must be one matplotlib writes (.png, .svg, .pdf, ...)."""
    path = Path(path)
    _check_folder(path)
    _figure_kind(path, _figure_filetypes())


def _check_folder(path: Path) -> None:
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.exists():
        raise ValueError(f"{path}: folder {folder} does not exist")
    if not folder.is_dir():
        raise ValueError(f"{path}: {folder} is a file, not a folder")
    if path.is_dir():
        raise ValueError(f"{path}: is a folder; give a file name such as {path / 'out.png'}")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ValueError(f"{path}: folder {folder} is not writable")


def _image_format_of(path: Path) -> str:
    image_format = _image_format(path.suffix.lower())
    if image_format is None:
        raise ValueError(f"{path}: unknown image suffix {path.suffix!r}; use .png")
    return image_format


def _figure_filetypes() -> dict[str, str]:
    from matplotlib.backend_bases import FigureCanvasBase

    return FigureCanvasBase.get_supported_filetypes()


def _figure_kind(path: Path, supported) -> str:
    if not path.suffix:
        raise ValueError(f"{path}: give the figure file a suffix such as .png, .svg or .pdf")
    kind = path.suffix[1:].lower()
    if kind not in supported:
        raise ValueError(f"{path}: matplotlib cannot write {path.suffix!r} figures; use .png")
    return kind


def _image_format(suffix: str) -> str | None:
    """Pillow's format name for a file suffix such as ".png", or None."""
    Image.preinit()  # the common formats, PNG among them, without importing every plugin
    if suffix not in Image.EXTENSION:
        Image.init()  # all the others: importing every plugin is slow, so only when asked
    return Image.EXTENSION.get(suffix)


# A figure a back row can read (docs/lecturers.md, "Figures a back row can read"): projected to
# fill a 1920 x 1080 screen, whichever way it fits, its smallest text is at least 1/40 of the
# screen's height (27 px), and it is blown up at most 1.6 times. For a figure W x H pixels with
# its smallest text t pixels (the font size: points x dpi / 72) that is
#     t >= max(H / 40, W / 71.1)   and   W >= 1200 or H >= 675,
# and every figure is stored at FIGURE_DPI or more. tests/test_figures_legible.py checks each
# stored figure; the smallest text is written into the PNG (TEXT_KEY) as the figure is saved.
FIGURE_DPI = 150
TEXT_KEY = "raykit smallest text px"
SCREEN = (1920, 1080)
SMALLEST_SCREEN_TEXT = SCREEN[1] / 40  # 27 px
LARGEST_ENLARGEMENT = 1.6


def smallest_text_px(figure, dpi: float) -> float | None:
    """The font size, in pixels at ``dpi``, of the smallest text ``figure`` draws (only text it
    really draws: not the tick labels of an axis turned off, not empty labels); None without
    text."""
    from matplotlib.text import Text

    sizes: list[float] = []
    draw = Text.draw

    def recording_draw(self, renderer):
        if self.get_visible() and self.get_text().strip():
            sizes.append(self.get_fontsize())
        return draw(self, renderer)

    Text.draw = recording_draw
    try:
        figure.canvas.draw()
    finally:
        Text.draw = draw
    return min(sizes) * dpi / 72 if sizes else None


def legibility_problems(
    width: int, height: int, dpi: float | None, text_px: float | None
) -> list[str]:
    """What keeps a stored figure of ``width`` x ``height`` pixels, saved at ``dpi`` with its
    smallest text ``text_px`` pixels, from being read on a projector (the rule above); [] when
    nothing does."""
    problems = []
    if dpi is None or dpi < FIGURE_DPI - 0.5:
        problems.append(f"stored at {dpi} dpi, under {FIGURE_DPI}")
    scale = min(SCREEN[0] / width, SCREEN[1] / height)
    if scale > LARGEST_ENLARGEMENT:
        problems.append(
            f"{width} x {height} px is blown up {scale:.2f} times to fill a {SCREEN[0]} x "
            f"{SCREEN[1]} screen (at most {LARGEST_ENLARGEMENT})"
        )
    if text_px is not None and text_px * scale < SMALLEST_SCREEN_TEXT - 0.05:
        problems.append(
            f"its smallest text, {text_px:.1f} px, is {text_px * scale:.1f} px on the screen "
            f"(at least {SMALLEST_SCREEN_TEXT:.0f}: {max(height / 40, width / 71.1):.1f} px here)"
        )
    return problems


def _stored_size(figure, dpi: float, tight: bool) -> tuple[float, float]:
    """The pixels ``figure`` is stored at: its whole canvas, or (``tight``) what it draws plus
    savefig's margin (pad_inches, 0.1 inch a side)."""
    if tight:
        box = figure.get_tightbbox(figure.canvas.get_renderer())
        return (box.width + 0.2) * dpi, (box.height + 0.2) * dpi
    width, height = figure.get_size_inches()
    return width * dpi, height * dpi


def fit_for_projector(figure, dpi: float, tight: bool = False) -> float:
    """Make ``figure`` keep the projector rule above, and return the dpi to store it at: where
    its smallest text is under 1/40 of the screen, the figure is made smaller (the same text
    in fewer inches, so the text is a larger part of it); then, where it would be blown up more
    than 1.6 times, it is stored at more than ``dpi``. Text sizes and what is drawn stay."""
    for _ in range(8):
        text_px = smallest_text_px(figure, dpi)
        if text_px is None:
            break
        width, height = _stored_size(figure, dpi, tight)
        # 3% to spare: a tight crop's stored size can differ a little from this estimate
        needed = 1.03 * SMALLEST_SCREEN_TEXT * max(width / SCREEN[0], height / SCREEN[1])
        if text_px >= needed:
            break
        figure.set_size_inches(figure.get_size_inches() * max(0.5, 0.98 * text_px / needed))
    width, height = _stored_size(figure, dpi, tight)
    scale = min(SCREEN[0] / width, SCREEN[1] / height)
    if scale > LARGEST_ENLARGEMENT:
        dpi = float(np.ceil(dpi * scale / LARGEST_ENLARGEMENT * 1.01))
    return dpi


def figure_png(figure, dpi: float = FIGURE_DPI, **savefig_options) -> bytes:
    """``figure`` as PNG bytes, fitted to the projector rule (:func:`fit_for_projector`, at
    ``dpi`` or more), with its smallest text's size written in (TEXT_KEY)."""
    import io

    tight = savefig_options.get("bbox_inches") == "tight"
    dpi = fit_for_projector(figure, dpi, tight)
    text_px = smallest_text_px(figure, dpi)
    metadata = {TEXT_KEY: "none" if text_px is None else f"{text_px:.2f}"}
    stream = io.BytesIO()
    figure.savefig(stream, format="png", dpi=dpi, metadata=metadata, **savefig_options)
    return stream.getvalue()


NOTEBOOK_DPI = 200  # the notebooks' figures are small (a few inches): stored finer


def show_figures_legibly(dpi: float = NOTEBOOK_DPI) -> None:
    """In a notebook: show each matplotlib figure as :func:`figure_png` stores it (at ``dpi``,
    cropped to what it draws, its smallest text written in), instead of the inline backend's
    default, so that the stored outputs are figures a projector shows legibly."""
    from IPython import get_ipython
    from matplotlib.figure import Figure

    shell = get_ipython()
    if shell is None:
        return
    formatter = shell.display_formatter.formatters["image/png"]
    formatter.for_type(Figure, lambda figure: figure_png(figure, dpi, bbox_inches="tight"))


def save_figure(figure, path: str | Path, dpi: int = FIGURE_DPI) -> None:
    """Write a matplotlib ``figure`` to ``path`` (format from the suffix), whole or not at all;
    a PNG carries the size of its smallest text (TEXT_KEY)."""
    path = Path(path)
    kind = _figure_kind(path, figure.canvas.get_supported_filetypes())
    if kind == "png":
        _write_whole(path, lambda stream: stream.write(figure_png(figure, dpi)))
        return
    _write_whole(path, lambda stream: figure.savefig(stream, format=kind, dpi=dpi))


def _write_whole(path: Path, write: Callable[[BinaryIO], None]) -> None:
    """Call ``write`` on a temporary file beside ``path``, then rename it to ``path``."""
    folder = path.parent if str(path.parent) else Path(".")
    try:
        handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=folder)
    except OSError as exc:  # name the user's path, not the hidden temporary file's
        raise OSError(exc.errno, exc.strerror, str(path)) from None
    try:
        with os.fdopen(handle, "wb") as stream:
            write(stream)
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp makes it private; give it the usual mode
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask

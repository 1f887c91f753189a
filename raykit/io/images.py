"""Images out: quantising float colours to 8 bits and writing files without half-written results.

Quantising follows the scene format: value = floor(clamp(c, 0, 1)·255 + 0.5), so halves round up
(0.3 -> 77), unlike numpy's round-half-to-even.
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

import numpy as np
from PIL import Image

from raykit.io.legibility import (
    LARGEST_ENLARGEMENT,
    SMALLEST_SCREEN_TEXT,
    Layout,
    measuring,
    png_with_layout,
    read_layout,
    screen_scale,
    text_problems,
)


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


# Figures are stored for a projector: raykit.io.legibility holds the rule and measures each
# figure as it is drawn into its PNG, which carries what was measured (LAYOUT_KEY).
FIGURE_DPI = 150  # the least a figure is stored at; more where it would be blown up
NOTEBOOK_DPI = 200  # the notebooks' figures are small (a few inches): stored finer


def _measured(figure, dpi: float, savefig_options: dict) -> Layout:
    """``figure`` drawn as :func:`figure_png` would store it at ``dpi``, measured (unencoded)."""
    import io

    with measuring(figure) as layout:
        figure.savefig(io.BytesIO(), format="rgba", dpi=dpi, **savefig_options)
    return layout


def fit_for_projector(figure, dpi: float, **savefig_options) -> float:
    """Make ``figure`` keep the projector rule (:mod:`raykit.io.legibility`), and return the
    dpi to store it at: where its smallest text, as drawn, is under 1/40 of the screen, the
    figure is made smaller (the same text in fewer inches, so the text is a larger part of it);
    then, where it would be blown up more than 1.6 times, it is stored at more than ``dpi``.
    Text sizes and what is drawn stay."""
    for _ in range(8):
        layout = _measured(figure, dpi, savefig_options)
        text_px = layout.smallest_text_px
        if text_px is None:
            break
        # 3% to spare: a tight crop's stored size moves a little as the figure shrinks
        needed = 1.03 * SMALLEST_SCREEN_TEXT / screen_scale(*layout.size)
        if text_px >= needed:
            break
        figure.set_size_inches(figure.get_size_inches() * max(0.5, 0.98 * text_px / needed))
    layout = _measured(figure, dpi, savefig_options)
    scale = screen_scale(*layout.size)
    if scale > LARGEST_ENLARGEMENT:
        dpi = float(np.ceil(dpi * scale / LARGEST_ENLARGEMENT * 1.01))
    return dpi


def figure_png(figure, dpi: float = FIGURE_DPI, **savefig_options) -> bytes:
    """``figure`` as PNG bytes, fitted to the projector rule (:func:`fit_for_projector`, at
    ``dpi`` or more), carrying what its draw into the PNG measured (LAYOUT_KEY: its size, each
    text's box and line height, its images, and :func:`raykit.io.legibility.layout_problems`)."""
    import io

    dpi = fit_for_projector(figure, dpi, **savefig_options)
    stream = io.BytesIO()
    with measuring(figure) as layout:
        figure.savefig(stream, format="png", dpi=dpi, **savefig_options)
    return png_with_layout(stream.getvalue(), layout)


def show_figures_legibly(dpi: float = NOTEBOOK_DPI) -> None:
    """In a notebook: show each matplotlib figure as :func:`figure_png` stores it (at ``dpi``,
    cropped to what it draws, its measured layout written in), instead of the inline backend's
    default, so that the stored outputs are figures a projector shows legibly; what keeps a
    figure from it (text too small, cut off, on other text or on a line) is printed under it."""
    from IPython import get_ipython
    from matplotlib.figure import Figure

    shell = get_ipython()
    if shell is None:
        return

    def shown(figure) -> bytes:
        png = figure_png(figure, dpi, bbox_inches="tight")
        layout = read_layout(png)
        for problem in layout.problems + text_problems(*layout.size, layout.smallest_text_px):
            print(f"raykit: this figure will not read on a projector: {problem}", file=sys.stderr)
        return png

    shell.display_formatter.formatters["image/png"].for_type(Figure, shown)


def save_figure(figure, path: str | Path, dpi: int = FIGURE_DPI) -> None:
    """Write a matplotlib ``figure`` to ``path`` (format from the suffix), whole or not at all;
    a PNG is fitted to the projector and carries its measured layout (:func:`figure_png`)."""
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

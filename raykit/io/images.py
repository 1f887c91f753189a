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


def save_figure(figure, path: str | Path, dpi: int = 120) -> None:
    """Write a matplotlib ``figure`` to ``path`` (format from the suffix), whole or not at all."""
    path = Path(path)
    kind = _figure_kind(path, figure.canvas.get_supported_filetypes())
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

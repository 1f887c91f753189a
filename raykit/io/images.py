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
    image_format = _image_format(path.suffix.lower())
    if image_format is None:
        raise ValueError(f"{path}: unknown image suffix {path.suffix!r}; use .png")
    if pixels.dtype != np.uint8:
        pixels = quantize(pixels)
    _write_whole(path, lambda stream: Image.fromarray(pixels).save(stream, format=image_format))


def _image_format(suffix: str) -> str | None:
    """Pillow's format name for a file suffix such as ".png", or None."""
    Image.preinit()  # the common formats, PNG among them, without importing every plugin
    if suffix not in Image.EXTENSION:
        Image.init()  # all the others: this import costs about 25 ms
    return Image.EXTENSION.get(suffix)


def save_figure(figure, path: str | Path, dpi: int = 120) -> None:
    """Write a matplotlib ``figure`` to ``path`` (format from the suffix), whole or not at all."""
    path = Path(path)
    if not path.suffix:
        raise ValueError(f"{path}: give the figure file a suffix such as .png, .svg or .pdf")
    kind = path.suffix[1:].lower()
    if kind not in figure.canvas.get_supported_filetypes():
        raise ValueError(f"{path}: matplotlib cannot write {path.suffix!r} figures; use .png")
    _write_whole(path, lambda stream: figure.savefig(stream, format=kind, dpi=dpi))


def _write_whole(path: Path, write: Callable[[BinaryIO], None]) -> None:
    """Call ``write`` on a temporary file beside ``path``, then rename it to ``path``."""
    folder = path.parent if str(path.parent) else Path(".")
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=folder)
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

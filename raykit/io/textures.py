"""Textures: any PNG Pillow reads, as an 8-bit RGBA array, decoded only when first used.

Convention: ``rgba`` is ``(H, W, 4)`` uint8 with row 0 the *top* row of the image, as Pillow and
the PNG store it. Grey, palette (with or without transparency), RGB, RGBA and 16-bit images are
all converted to this one form; an image without alpha is opaque. Which texels are holes is the
billboard's rule (:data:`raykit.billboards.OPAQUE_FROM`).

Opening a file reads only its header, which is enough to reject a missing file, a file that is
no image, or an absurd size, at scene-load time. The pixels are decoded on first access of
:attr:`Texture.rgba`, so a texture no ray reaches costs nothing.
"""

from __future__ import annotations

import warnings
from functools import cached_property
from pathlib import Path

import numpy as np
from PIL import Image, UnidentifiedImageError

from raykit.io.errors import SceneError

MAX_TEXTURE_SIDE = 16384
MAX_TEXTURE_PIXELS = 64 * 1024 * 1024


class Texture:
    """A texture file; ``source`` and ``field`` name it in error messages."""

    def __init__(self, path: Path, source: str, field: str) -> None:
        self.path = Path(path)
        self.source = source
        self.field = field
        self.width, self.height = self._read_header()

    def _error(self, problem: str) -> SceneError:
        return SceneError(self.source, self.field, problem)

    def _open(self) -> Image.Image:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            try:
                return Image.open(self.path)
            except FileNotFoundError:
                raise self._error(f"texture file not found: {self.path}") from None
            except IsADirectoryError:
                raise self._error(f"texture path is a folder, not an image: {self.path}") from None
            except PermissionError:
                raise self._error(f"texture file cannot be read: {self.path}") from None
            except UnidentifiedImageError:
                raise self._error(f"not an image Pillow can read: {self.path}") from None
            except (Image.DecompressionBombError, Image.DecompressionBombWarning):
                raise self._error(f"texture is too large to be sane: {self.path}") from None
            except OSError as exc:
                raise self._error(f"texture file cannot be read: {self.path} ({exc})") from None

    def _read_header(self) -> tuple[int, int]:
        with self._open() as image:
            width, height = image.size
        if (
            width > MAX_TEXTURE_SIDE
            or height > MAX_TEXTURE_SIDE
            or width * height > MAX_TEXTURE_PIXELS
        ):
            raise self._error(
                f"texture is too large to be sane: {width}x{height} pixels "
                f"(at most {MAX_TEXTURE_SIDE} a side and {MAX_TEXTURE_PIXELS} in all)"
            )
        return width, height

    @cached_property
    def rgba(self) -> np.ndarray:
        """The texels, ``(H, W, 4)`` uint8, row 0 at the top; decoded on first use."""
        try:
            with self._open() as image:
                return to_rgba8(image)
        except SceneError:
            raise
        except (OSError, ValueError, SyntaxError) as exc:
            raise self._error(f"texture cannot be decoded: {self.path} ({exc})") from None


def to_rgba8(image: Image.Image) -> np.ndarray:
    """Any Pillow image as ``(H, W, 4)`` uint8 RGBA.

    Pillow's own ``convert`` clips 16-bit grey (modes ``I;16`` and ``I``) at 255 instead of
    scaling it, so those are scaled down to 8 bits here first.
    """
    if image.mode.startswith("I"):
        grey = np.asarray(image, dtype=np.int64)
        image = Image.fromarray((np.clip(grey, 0, 65535) >> 8).astype(np.uint8), "L")
    elif image.mode == "F":
        grey = np.asarray(image, dtype=np.float64)
        image = Image.fromarray(np.clip(grey, 0, 255).astype(np.uint8), "L")
    return np.asarray(image if image.mode == "RGBA" else image.convert("RGBA"))

"""Textures: any PNG Pillow reads, as an 8-bit RGBA array, decoded only when first used.

Convention: ``rgba`` is ``(H, W, 4)`` uint8 with row 0 the *top* row of the image, as Pillow and
the PNG store it. Grey, palette (with or without transparency), RGB, RGBA and 16-bit images are
all converted to this one form; an image without alpha is opaque. Which texels are holes is the
billboard's rule (:data:`raykit.billboards.OPAQUE_FROM`).

Opening a file reads only its header, which is enough to reject a missing file, a file that is
no image, or an absurd size, at scene-load time. The pixels are decoded on first access of
:attr:`Texture.rgba`, so a texture no ray reaches costs nothing.

Decoded once. A texture of :data:`CACHED_FROM` texels or more is kept, decoded, in a cache on
disk (:func:`cache_folder`), under a hash of the file's bytes, of Pillow's version and of
:data:`CACHE_FORMAT`, so an edited file, another Pillow or another conversion is decoded anew,
never served from an older one. A kept decode is the texels' bytes alone, row by row (the
texture's header gives their shape, and a file of another size is no decode): read back, they
are the same bytes the decode made, for less than a ``.npy`` file's header costs to parse.
The cache keeps at most :data:`CACHE_BYTES`, the least recently used going first (a process
looks at what the folder holds when its own writes may have filled it, so writes of others since
its last look may overfill it until then); a cache that cannot be written or read is no cache
(the texture is decoded, as without one). Smaller textures decode faster than a file is
written, and are decoded each time.

Textures may be decoded on several threads at once (Pillow lets go of Python's lock while it
inflates a PNG), as the compiled engine's ``prepare`` decodes a scene's.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import os
import threading
import warnings
from pathlib import Path

import numpy as np
import PIL
from PIL import Image, UnidentifiedImageError

from raykit.io.errors import SceneError

MAX_TEXTURE_SIDE = 16384
MAX_TEXTURE_PIXELS = 64 * 1024 * 1024
CACHED_FROM = 256 * 256  # texels: a texture this large or larger is cached once decoded
CACHE_BYTES = 512 * 1024 * 1024  # at most this many bytes of decoded textures on disk
CACHE_FORMAT = 2  # raise it when to_rgba8 or the kept file changes, so no older decode is read
CACHE_SUFFIX = ".rgba"  # a kept decode's; a file being written ends in ".part"


class Texture:
    """A texture file; ``source`` and ``field`` name it in error messages."""

    def __init__(self, path: Path, source: str, field: str) -> None:
        self.path = Path(path)
        self.source = source
        self.field = field
        self.width, self.height = self._read_header()
        self._rgba: np.ndarray | None = None
        self._missed: tuple[Path, str, bytes] | None = None  # where in_cache found no decode

    def _error(self, problem: str) -> SceneError:
        return SceneError(self.source, self.field, problem)

    def _open(self, content: bytes | None = None) -> Image.Image:
        """The file opened by Pillow; ``content``: its bytes, already read."""
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            try:
                return Image.open(self.path if content is None else io.BytesIO(content))
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

    @property
    def decoded(self) -> bool:
        """Whether the texels have been decoded (or read from the cache) yet: a texture no ray
        reaches never is."""
        return self._rgba is not None

    @property
    def rgba(self) -> np.ndarray:
        """The texels, ``(H, W, 4)`` uint8, row 0 at the top; decoded on first use, or read
        from the cache of decoded textures (a large one, see the module's page), and kept,
        so that :attr:`decoded` can tell."""
        if self._rgba is None and not self.in_cache():
            self._rgba = self._decoded_and_kept()
        return self._rgba

    @property
    def large(self) -> bool:
        """Whether the texture has :data:`CACHED_FROM` texels or more: kept in the cache once
        decoded, and long to decode."""
        return self.width * self.height >= CACHED_FROM

    def in_cache(self) -> bool:
        """Whether :attr:`rgba` is at hand without a decode: got already, or read now from the
        cache of decoded textures (and kept). Never for a small texture not yet decoded, which
        is not cached. Looking costs a read of the file and its hash, which a decode after it
        does not repeat."""
        if self._rgba is not None:
            return True
        if self._missed is not None:  # looked already
            return False
        folder = cache_folder() if self.large else None
        if folder is None:
            return False
        try:
            content = self.path.read_bytes()
        except OSError:
            return False  # the decode words the error
        key = _cache_key(content)
        self._rgba = _cached(folder / f"{key}{CACHE_SUFFIX}", (self.height, self.width, 4))
        if self._rgba is None:
            self._missed = (folder, key, content)
        return self._rgba is not None

    def _decoded_and_kept(self) -> np.ndarray:
        """The texels decoded, and kept in the cache when it lacked them (:meth:`in_cache`,
        which looked first, says where and under what name)."""
        missed, self._missed = self._missed, None
        if missed is None:
            return self._decode()
        folder, key, content = missed
        rgba = self._decode(content)
        if rgba.shape == (self.height, self.width, 4):
            _keep(folder, key, rgba)
        return rgba

    def _decode(self, content: bytes | None = None) -> np.ndarray:
        try:
            with self._open(content) as image:
                return to_rgba8(image)
        except SceneError:
            raise
        except (OSError, ValueError, SyntaxError) as exc:
            raise self._error(f"texture cannot be decoded: {self.path} ({exc})") from None


def cache_folder() -> Path | None:
    """The decoded textures' folder, ``raykit/textures`` under ``$RAYKIT_CACHE_DIR``, else
    ``$XDG_CACHE_HOME`` or ``~/.cache``, as the compiled kernels' cache
    (:func:`raykit.engine.choice.cache_folder`): the first that can be made; None if none
    can."""
    bases = (
        os.environ.get("RAYKIT_CACHE_DIR"),
        os.environ.get("XDG_CACHE_HOME"),
        os.path.join(os.path.expanduser("~"), ".cache"),
    )
    for base in filter(None, bases):
        folder = Path(base) / "raykit" / "textures"
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError:
            continue
        return folder
    return None


def _cache_key(content: bytes) -> str:
    """The cache's name for a file's decode: its bytes, Pillow's version, the cache's format.
    SHA-256, not BLAKE2b: hashlib hands it to OpenSSL, which uses the processor's SHA
    instructions where it has them, and the key is most of what reading a cached texture
    costs."""
    digest = hashlib.sha256(content)
    digest.update(f"\0{PIL.__version__}\0{CACHE_FORMAT}".encode())
    return digest.hexdigest()


def _cached(path: Path, shape: tuple[int, int, int]) -> np.ndarray | None:
    """The decode kept at ``path``, if it is there and of ``shape`` (uint8, as many bytes); it
    is marked as used now, for :func:`_evict`."""
    rgba = np.empty(shape, np.uint8)
    try:
        with open(path, "rb", buffering=0) as file:
            if os.fstat(file.fileno()).st_size != rgba.nbytes:
                return None
            if file.readinto(memoryview(rgba).cast("B")) != rgba.nbytes:
                return None
        os.utime(path)
    except OSError:
        return None
    rgba.flags.writeable = False  # as a decode's, which are Pillow's bytes
    return rgba


# Per cache folder, the bytes this process may still write into it before it looks at the
# folder again (:func:`_evict`): a look stats every file, and most writes leave the cache far
# below CACHE_BYTES. Another process's writes are seen at this one's next look.
_room: dict[Path, int] = {}
_room_lock = threading.Lock()  # threads that decode at once keep their decodes at once


def _keep(folder: Path, key: str, rgba: np.ndarray) -> None:
    """Write ``rgba`` into the cache ``folder`` under ``key`` (whole: a temporary file, then a
    rename); then, if this process's writes may have filled the cache since it last looked,
    remove the least recently used decodes while it holds more than :data:`CACHE_BYTES`. A
    cache that cannot be written is left as it is."""
    part = folder / f"{key}.{os.getpid()}.{threading.get_ident()}.part"  # this thread's own
    try:
        with open(part, "wb", buffering=0) as file:
            left = memoryview(np.ascontiguousarray(rgba)).cast("B")
            while left:
                left = left[file.write(left) :]
        os.replace(part, folder / f"{key}{CACHE_SUFFIX}")
        with _room_lock:
            room = _room.get(folder, 0) - rgba.nbytes  # a folder not yet looked at: look now
            _room[folder] = room if room >= 0 else CACHE_BYTES - _evict(folder)
    except OSError:
        with contextlib.suppress(OSError):
            part.unlink(missing_ok=True)


def _evict(folder: Path) -> int:
    """Remove the least recently used decodes from ``folder`` until it holds at most
    :data:`CACHE_BYTES` (another process may be removing them too); the bytes it holds
    then."""
    kept = []
    with os.scandir(folder) as entries:
        for entry in entries:
            if entry.name.endswith(".part") or not entry.is_file(follow_symlinks=False):
                continue  # being written, or no decode
            try:
                status = entry.stat()
            except FileNotFoundError:
                continue
            kept.append((status.st_mtime, status.st_size, entry.path))
    total = sum(size for _, size, _ in kept)
    for _, size, path in sorted(kept, key=lambda kept: kept[0]):
        if total <= CACHE_BYTES:
            break
        Path(path).unlink(missing_ok=True)
        total -= size
    return total


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

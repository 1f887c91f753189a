"""Make the example scenes' textures: small procedural PNGs, no images of unknown origin.

    python scenes/textures/make_textures.py [OUT_FOLDER]

writes every texture into OUT_FOLDER (default: this folder). The tests regenerate them into a
temporary folder and compare the pixels with the committed files. Each texture also exercises
one of the PNG kinds the scene format accepts (RGB, RGBA, palette with transparency, 16-bit grey).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image


def checker(size: int = 16, squares: int = 8) -> Image.Image:
    """A two-tone checkerboard (RGB) with a red upper-left square to show orientation."""
    cell = size // squares
    yy, xx = np.mgrid[0:size, 0:size]
    light = ((yy // cell + xx // cell) % 2 == 0)[..., None]
    pixels = np.where(light, [225, 225, 215], [70, 90, 110]).astype(np.uint8)
    pixels[:cell, :cell] = [220, 40, 40]
    return Image.fromarray(pixels, "RGB")


def letter_f(size: int = 16) -> Image.Image:
    """A black "F" on yellow (RGB): asymmetric, so flips and mirror images are obvious."""
    pixels = np.full((size, size, 3), [250, 210, 60], dtype=np.uint8)
    s = size // 8
    pixels[s : 7 * s, 2 * s : 3 * s] = 0  # stem
    pixels[s : 2 * s, 2 * s : 6 * s] = 0  # top bar
    pixels[3 * s : 4 * s, 2 * s : 5 * s] = 0  # middle bar
    return Image.fromarray(pixels, "RGB")


def tree(width: int = 24, height: int = 32) -> Image.Image:
    """A cut-out sprite (RGBA): a green triangle crown on a brown trunk, transparent around."""
    pixels = np.zeros((height, width, 4), dtype=np.uint8)
    crown_rows = int(height * 0.75)
    for r in range(crown_rows):
        half = (r + 1) * (width / 2) / crown_rows
        c0, c1 = int(round(width / 2 - half)), int(round(width / 2 + half))
        shade = 90 + (60 * r) // crown_rows
        pixels[r, c0:c1] = [30, shade, 40, 255]
    trunk = slice(width // 2 - width // 10, width // 2 + width // 10)
    pixels[crown_rows:, trunk] = [110, 70, 30, 255]
    return Image.fromarray(pixels, "RGBA")


def fence(width: int = 32, height: int = 12) -> Image.Image:
    """A picket fence (RGBA): slats and two rails, transparent gaps between them."""
    pixels = np.zeros((height, width, 4), dtype=np.uint8)
    wood = [200, 170, 120, 255]
    for c in range(0, width, 4):
        pixels[1:, c : c + 2] = wood
        pixels[0, c : c + 2][:, 3] = 0  # pointed tops: the first row stays clear
    pixels[3:5] = wood
    pixels[8:10] = wood
    return Image.fromarray(pixels, "RGBA")


def window(size: int = 12) -> Image.Image:
    """A palette image with a transparent index: a blue frame with a see-through centre."""
    indices = np.ones((size, size), dtype=np.uint8)
    indices[2:-2, 2:-2] = 0  # index 0 is transparent
    indices[size // 2 - 1 : size // 2 + 1, :] = 2  # a white cross bar
    indices[:, size // 2 - 1 : size // 2 + 1] = 2
    image = Image.fromarray(indices, "P")
    image.putpalette([0, 0, 0, 40, 60, 160, 240, 240, 240])
    image.info["transparency"] = 0
    return image


def ramp16(width: int = 16, height: int = 4) -> Image.Image:
    """A 16-bit grey ramp, dark on the left to white on the right (mode I;16)."""
    values = np.linspace(0, 65535, width).round().astype(np.uint16)
    return Image.fromarray(np.tile(values, (height, 1)))


def car_side(width: int = 40) -> Image.Image:
    """One row (RGB): a car's side from the front bumper to the rear one, for line-scan scenes."""
    palette = {
        "b": [60, 60, 60],  # bumper
        "r": [200, 30, 40],  # body
        "l": [255, 240, 150],  # lamp
        "g": [150, 200, 235],  # glass
        "k": [25, 25, 25],  # pillar
    }
    side = "bblrrrrrggggggkgggggggkggggrrrrrrrrrllbb"
    assert len(side) == width
    return Image.fromarray(np.array([[palette[c] for c in side]], np.uint8), "RGB")


def parts(width: int = 24) -> Image.Image:
    """Three rows (RGBA), one per part on the conveyor: row 0 a good plate, row 1 a plate with
    a hole (transparent texels), row 2 a plate with a bad spot."""
    rows = np.zeros((3, width, 4), dtype=np.uint8)
    rows[:] = [90, 120, 160, 255]
    rows[:, ::6] = [40, 50, 70, 255]  # bolts
    rows[1, width // 2 - 3 : width // 2 + 3, 3] = 0
    rows[2, width // 3 : width // 3 + 2] = [230, 120, 20, 255]
    return Image.fromarray(rows, "RGBA")


TEXTURES = {
    "checker.png": checker,
    "letter_f.png": letter_f,
    "tree.png": tree,
    "fence.png": fence,
    "window.png": window,
    "ramp16.png": ramp16,
    "car_side.png": car_side,
    "parts.png": parts,
}


def main(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for name, make in TEXTURES.items():
        make().save(folder / name)
        print(f"wrote {folder / name}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent)

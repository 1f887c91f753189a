"""Benchmark scenes made in code: the sphereflake and many small spheres.

sphereflake(level)   Eric Haines' recursive flake: a sphere with 9 spheres a third its size
                     around it, each with 9 around it, ... (level 4: 7,381 spheres), on a
                     ground billboard.
many_spheres(n)      n small spheres scattered in front of the camera.
lit_spheres(n)       n objects lit by a sun and a lamp: n - 1 spheres above a ground billboard
                     (mirrors=True: every other sphere a mirror).
classic_with_large_textures(folder)
                     scenes/classic.json (10 spheres, 4 textured billboards) with each
                     texture made 256 x 256 RGBA, written as a scene file and PNGs in folder.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from raykit.io.scene_json import scene_from_dict
from raykit.rays import dot, normalize
from raykit.scene import Scene


def _directions() -> np.ndarray:
    """The 9 child directions about +z ``(9, 3)``: 6 around the equator, 3 raised 60 degrees.

    Written with exact constants (cos and sin of multiples of 30 degrees are 0, ±1/2, ±1 and
    ±√3/2) rather than numpy's vectorised cos and sin, whose last bit differs between processors.
    """
    half, root = 0.5, math.sqrt(3) / 2
    around = [(1.0, 0.0), (half, root), (-half, root), (-1.0, 0.0), (-half, -root), (half, -root)]
    raised = [(root, half), (-root, half), (0.0, -1.0)]  # at 30, 150 and 270 degrees
    return np.array(
        [(x, y, 0.0) for x, y in around] + [(half * x, half * y, root) for x, y in raised]
    )


def _frame_to(axis: np.ndarray) -> np.ndarray:
    """A rotation ``(3, 3)`` taking +z to ``axis``: its columns are the new x, y and z."""
    z = normalize(axis)
    helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = normalize(np.cross(helper, z))
    return np.column_stack([x, np.cross(z, x), z])


def _rotated(directions: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    """``directions (N, 3)`` turned by ``rotation (3, 3)``, each row's sums taken left to right
    (:func:`raykit.rays.dot`), not by a matrix product, whose order depends on BLAS."""
    return np.stack([dot(directions, row) for row in rotation], axis=-1)


def _camera(eye: list, lookat: list, fov_angle: float, width: int, height: int) -> dict:
    """A scene file's camera, y up."""
    return {"eye": eye, "lookat": lookat, "up": [0, 1, 0], "fov_angle": fov_angle,
            "width": width, "height": height}  # fmt: skip


def sphereflake(level: int, width: int = 512, height: int = 512) -> Scene:
    return scene_from_dict(sphereflake_dict(level, width, height))


def sphereflake_dict(level: int, width: int = 512, height: int = 512) -> dict:
    """The sphereflake as a scene file's contents (what :func:`sphereflake` loads)."""
    spheres = []
    palette = [
        [0.85, 0.25, 0.2],
        [0.95, 0.7, 0.2],
        [0.3, 0.7, 0.35],
        [0.25, 0.45, 0.85],
        [0.7, 0.4, 0.8],
    ]

    def grow(center, radius, axis, depth):
        spheres.append(
            {"center": center.tolist(), "radius": radius, "color": palette[depth % len(palette)]}
        )
        if depth == level:
            return
        rotation = _frame_to(axis)
        for direction in _rotated(_directions(), rotation):
            grow(center + direction * (radius + radius / 3), radius / 3, direction, depth + 1)

    grow(np.array([0.0, 1.0, 0.0]), 1.0, np.array([0.0, 1.0, 0.0]), 0)
    camera = _camera([2.1, 3.3, 4.6], [0, 1.1, 0], 45, width, height)
    ground = {
        "upper_left": [-6, -0.6, -6],
        "upper_right": [6, -0.6, -6],
        "lower_left": [-6, -0.6, 6],
        "color": [0.6, 0.6, 0.55],
    }
    return {
        "camera": camera,
        "background": [0.75, 0.85, 1.0],
        "spheres": spheres,
        "billboards": [ground],
    }


def many_spheres(count: int, width: int = 1920, height: int = 1080, seed: int = 0) -> Scene:
    rng = np.random.default_rng(seed)
    spheres = [
        {
            "center": rng.uniform([-8, -4.5, -30], [8, 4.5, -5]).tolist(),
            "radius": float(rng.uniform(0.05, 0.3)),
            "color": rng.uniform(0, 1, 3).tolist(),
        }
        for _ in range(count)
    ]
    camera = _camera([0, 0, 5], [0, 0, 0], 50, width, height)
    return scene_from_dict({"camera": camera, "background": [0.05, 0.05, 0.1], "spheres": spheres})


def lit_spheres(
    count: int, mirrors: bool = False, width: int = 320, height: int = 240, seed: int = 0
) -> Scene:
    """``count`` objects, lit: ``count - 1`` spheres scattered above a ground billboard, their
    radii shrinking as their number grows (as the cube root), so that they crowd the picture
    alike; with ``mirrors``, every other sphere a mirror (max_depth 4)."""
    rng = np.random.default_rng(seed)
    scale = 2.0 / max(1, count - 1) ** (1 / 3)
    spheres = []
    for k in range(count - 1):
        sphere = {
            "center": rng.uniform([-3, 0.3, -3], [3, 2.5, 1.5]).tolist(),
            "radius": float(rng.uniform(0.4, 0.8) * scale),
            "color": rng.uniform(0.2, 0.9, 3).tolist(),
            "specular": [0.4, 0.4, 0.4],
            "shininess": 40,
        }
        if mirrors and k % 2 == 0:
            sphere["mirror"] = [0.8, 0.8, 0.8]
        spheres.append(sphere)
    ground = {
        "upper_left": [-6, 0, -6],
        "upper_right": [6, 0, -6],
        "lower_left": [-6, 0, 6],
        "color": [0.6, 0.6, 0.55],
    }
    camera = _camera([0, 3, 7], [0, 1, 0], 45, width, height)
    lights = [
        {"type": "directional", "direction": [-0.4, -1.0, -0.6], "color": [0.7, 0.7, 0.65]},
        {"type": "point", "position": [3.0, 5.0, 4.0], "color": [0.45, 0.45, 0.5]},
    ]
    data = {
        "camera": camera,
        "background": [0.55, 0.7, 0.9],
        "ambient": [0.2, 0.2, 0.22],
        "lights": lights,
        "spheres": spheres,
        "billboards": [ground],
    }
    if mirrors:
        data["max_depth"] = 4
    return scene_from_dict(data)


TEXTURE_SIDE = 256
CLASSIC = Path(__file__).resolve().parent.parent / "scenes" / "classic.json"


def classic_with_large_textures(folder: Path, side: int = TEXTURE_SIDE, seed: int = 0) -> Path:
    """scenes/classic.json with each billboard's texture made ``side`` x ``side`` RGBA: the
    original scaled up (nearest texel, so the picture keeps its look) with a seeded grain of
    up to ±8 in each colour channel, so that the PNG holds as much detail as a photograph's
    and costs as much to decode; alpha as in the original. Writes the scene file and its
    textures into ``folder`` and returns the scene file's path."""
    from PIL import Image

    from raykit.io.textures import to_rgba8

    rng = np.random.default_rng(seed)
    folder.mkdir(parents=True, exist_ok=True)
    data = json.loads(CLASSIC.read_text())
    for k, board in enumerate(data["billboards"]):
        with Image.open(CLASSIC.parent / board["image"]) as image:
            small = to_rgba8(image)
        rows = np.arange(side) * small.shape[0] // side
        cols = np.arange(side) * small.shape[1] // side
        large = small[rows[:, None], cols[None, :]].astype(np.int16)
        large[..., :3] += rng.integers(-8, 9, (side, side, 3), dtype=np.int16)
        texture = folder / f"texture_{k}.png"
        Image.fromarray(np.clip(large, 0, 255).astype(np.uint8), "RGBA").save(texture)
        board["image"] = texture.name
    data.pop("$schema", None)
    path = folder / "classic_large_textures.json"
    path.write_text(json.dumps(data, indent=1))
    return path

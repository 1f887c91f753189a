"""What the compiled engine's tests share: seeded random rays and scenes, a bit-for-bit
comparison, whole renders compared with both engines, and the twin table's generated tests
(:func:`twin_test`)."""

from __future__ import annotations

import importlib
import io
import json
import os
import subprocess
import sys
from collections.abc import Callable
from dataclasses import replace

import numpy as np
import pytest
from libm_power import libm_power

from conftest import REPO, SCENES, shifted_scene
from raykit.billboards import Billboard
from raykit.camera import Camera
from raykit.engine import compiled
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.lights import DirectionalLight, PointLight
from raykit.materials import Material
from raykit.render import render
from raykit.scene import Scene
from raykit.spheres import Sphere

RAYS = 100_000


EPS = np.finfo(float).eps


def random_rays(rng, count, scale=10.0):
    origins = rng.normal(size=(count, 3)) * scale
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return origins, directions


def rays_into_crowd(rng, count):
    """``count`` rays from around a :func:`crowd`, each aimed at a point inside it."""
    origins, _ = random_rays(rng, count, 6.0)
    toward = rng.normal(size=(count, 3)) * 4 - origins
    return origins, toward / np.linalg.norm(toward, axis=1, keepdims=True)


def exactly(a, b):
    """Equal bit for bit, NaN where NaN, and the same sign of zero."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    assert same.all(), f"{(~same).sum()} of {a.size} differ, first at {np.argwhere(~same)[0]}"
    assert np.array_equal(np.signbit(a), np.signbit(b))


def board_scene(rng, texture=None):
    corner = rng.normal(size=3) * 3
    a, b = rng.normal(size=3) * 2, rng.normal(size=3) * 2
    board = Billboard(corner, corner + b, corner + a, color=rng.uniform(size=3), texture=texture)
    camera = Camera(np.zeros(3), np.array([0, 0, -1.0]), np.array([0, 1.0, 0]), 60, 8, 8)
    return Scene(camera, billboards=(board,)), board


class Texels:
    def __init__(self, rgba):
        self.rgba, self.height, self.width = rgba, rgba.shape[0], rgba.shape[1]


def crowd(rng, count, ties=True, holes=True):
    """A random scene of spheres and billboards with exact ties (repeated spheres) and
    cut-out textures."""
    spheres = [
        Sphere(rng.normal(size=3) * 4, float(rng.uniform(0.2, 1.5)), rng.uniform(size=3))
        for _ in range(count)
    ]
    if ties:
        spheres += [replace(s, color=rng.uniform(size=3)) for s in spheres[: count // 4]]
    boards = []
    for k in range(4):
        rgba = rng.integers(0, 256, size=(5, 6, 4), dtype=np.uint8)
        corner = rng.normal(size=3) * 4
        a, b = rng.normal(size=3) * 3, rng.normal(size=3) * 3
        texture = Texels(rgba) if holes and k % 2 else None
        boards.append(Billboard(corner, corner + b, corner + a, rng.uniform(size=3), texture))
    camera = Camera(np.array([0, 0, 20.0]), np.zeros(3), np.array([0, 1.0, 0]), 40, 64, 48)
    return Scene(camera, tuple(spheres), tuple(boards), background=np.array([0.1, 0.2, 0.3]))


def lit_crowd(rng, count):
    """A crowd with a point light, a directional light, ambient light, and materials: some
    shiny, some mirrors, some with their own diffuse colour."""
    scene = crowd(rng, count)

    def material(k):
        return Material(
            diffuse=rng.uniform(size=3) if k % 3 == 0 else None,
            specular=rng.uniform(size=3) if k % 2 else np.zeros(3),
            shininess=float(rng.choice([1.0, 8.0, 32.0, 100.0])),
            mirror=rng.uniform(0.2, 0.8, size=3) if k % 4 == 1 else np.zeros(3),
        )

    lights = (
        PointLight(np.array([3.0, 8.0, 10.0]), np.array([0.9, 0.8, 0.7])),
        DirectionalLight(np.array([-1.0, -2.0, -0.5]), np.array([0.3, 0.3, 0.4])),
    )
    return replace(
        scene,
        spheres=tuple(replace(s, material=material(k)) for k, s in enumerate(scene.spheres)),
        billboards=tuple(replace(b, material=material(k)) for k, b in enumerate(scene.billboards)),
        lights=lights,
        ambient=np.array([0.1, 0.1, 0.1]),
    )


def png(rgb) -> bytes:
    from PIL import Image

    from raykit.io.images import quantize

    buffer = io.BytesIO()
    Image.fromarray(quantize(rgb)).save(buffer, format="PNG")
    return buffer.getvalue()


def same_render(scene, **options):
    """The compiled render is the numpy render bit for bit once both take the same pow, and
    within 4 units in the last place of it (the PNG bytes the same) as the reference stands."""
    fast = render(scene, engine="compiled", **options)
    with libm_power():
        same_pow = render(scene, engine="numpy", **options)
    assert np.array_equal(fast.object_index, same_pow.object_index)
    exactly(fast.t, same_pow.t)
    exactly(fast.rgb, same_pow.rgb)
    numpy_image = render(scene, engine="numpy", **options)
    np.testing.assert_allclose(fast.rgb, numpy_image.rgb, rtol=4 * EPS, atol=0)
    assert png(fast.rgb) == png(numpy_image.rgb)


def small_render(name, **options):
    """A check that example scene ``name``, 48 x 32 pixels, renders the same with both engines
    (:func:`same_render`, with ``options``); it takes a generator, as a twin's check does."""
    scene = load_scene(SCENES / f"{name}.json")
    return lambda rng: same_render(
        replace(scene, camera=replace(scene.camera, width=48, height=32)), **options
    )


def two_threads() -> pytest.MarkDecorator:
    """Skips a test where numba has fewer than two threads to share the work."""
    import numba

    return pytest.mark.skipif(
        numba.config.NUMBA_NUM_THREADS < 2, reason="needs two threads to share the work"
    )


def run_python(code, cwd=REPO, **env):
    return subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=cwd,
        env={**os.environ, **env},
        timeout=600,
    )


def packet_scenes():
    rng = np.random.default_rng(7)
    data = json.loads((SCENES / "classic_lit.json").read_text())
    data.pop("$schema", None)
    moved = scene_from_dict(shifted_scene(data, [1e6, 1e6, 1e6]), folder=SCENES)
    small = lambda scene: replace(scene, camera=replace(scene.camera, width=70, height=45))  # noqa: E731
    return {
        "cutouts": small(load_scene(SCENES / "cutouts.json")),  # texels and holes
        "orthographic": small(load_scene(SCENES / "orthographic.json")),
        "classic_lit_at_1e6": small(moved),  # shaded, with shadow lists
        "crowd_with_ties": crowd(rng, 200),
    }


def ties_reversed(tiles):
    """The same tiles, with each tile's objects at the same closest t listed higher index
    first: the answer must not depend on it (a tie keeps the lower index, whatever the order)."""
    objects, entries = tiles.objects.copy(), tiles.entries.copy()
    for k in range(len(tiles.start) - 1):
        span = slice(tiles.start[k], tiles.start[k + 1])
        order = np.lexsort((-objects[span], entries[span, 4]))
        objects[span], entries[span] = objects[span][order], entries[span][order]
    return tiles._replace(objects=objects, entries=entries)


def kernels() -> dict:
    """Every numba kernel of the compiled engine's modules, by ``module.name`` (the twin
    table's names)."""
    from numba.core.dispatcher import Dispatcher
    from numba.core.extending import _Intrinsic

    found = {}
    for name, module in sorted(sys.modules.items()):
        if not name.startswith("raykit.engine.compiled.") or module is None:
            continue
        for attribute, value in vars(module).items():
            mine = getattr(value, "__module__", None) == name
            if mine and isinstance(value, Dispatcher | _Intrinsic):
                found[f"{name.rpartition('.')[2]}.{attribute}"] = value
    return found


def resolve(dotted: str):
    """The function a full dotted name names (a method as ``module.Class.method``), or None for a
    property or anything else that is data rather than a function."""
    parts = dotted.split(".")
    for split in range(len(parts) - 1, 0, -1):
        try:
            found = importlib.import_module(".".join(parts[:split]))
        except ImportError:
            continue
        for part in parts[split:]:
            found = vars(found).get(part) if isinstance(found, type) else getattr(found, part)
        if isinstance(found, classmethod | staticmethod):
            found = found.__func__
        return found if callable(found) else None
    return None


def twin_test(module: str, checks: dict[str, Callable[[np.random.Generator], None]]):
    """The differential test of each row of the twin table whose kernel is in ``module``, one per
    row: its check in ``checks`` (by the kernel's ``module.name``), given a seeded generator.
    A row with no check fails, naming the file to add it to."""
    from raykit.engine.compiled.twins import TWINS

    rows = [twin for twin in TWINS if twin.kernel.split(".")[0] == module]

    @pytest.mark.parametrize("twin", rows, ids=[twin.kernel for twin in rows])
    def test_the_twin_repeats_its_reference(twin):
        assert twin.kernel in checks, (
            f"{twin.kernel} repeats {twin.reference} with no differential check: add one to "
            f"CHECKS in tests/compiled/test_{module}.py"
        )
        checks[twin.kernel](np.random.default_rng(41))

    return test_the_twin_repeats_its_reference


def caster_answers_what_cast_answers(rng):
    """The compiled engine's caster (:func:`raykit.engine.compiled.render.cast_rays`, a
    :func:`raykit.engine.compiled.bvh.nearest_hit` per ray) against raykit.render.cast."""
    from raykit.render import cast

    scene = crowd(rng, 40)
    origins, directions = rays_into_crowd(rng, 20_000)
    expected = cast(scene, origins, directions)
    got = compiled.caster(scene)(origins, directions)
    assert np.array_equal(got.index, expected.index)
    exactly(got.t, expected.t)
    exactly(got.color, expected.color)


def distributed_scene(
    rng,
    sampler,
    *,
    lens=False,
    mirrors=False,
    samples=4,
    lights=True,
    glossy=False,
    moving=False,
    spheres=6,
):
    """A seeded random distributed scene (format v2, read as a file is) of 48 x 36 pixels:
    ``spheres`` spheres on a floor, in front of a textured wall, ``samples`` per pixel by
    ``sampler`` with a random seed; with ``lights``, an area light, a point light, a
    directional light and a physically based area light (and ambient light), else flat colours;
    a thin lens of random aperture and focus if ``lens``; mirror spheres and max_depth 2 if
    ``mirrors``, some of them glossy if ``glossy``; with ``moving``, a shutter [T0, T1] and
    every other sphere moving (motion blur), fast enough to cross the others."""
    balls = []
    for k in range(spheres):
        center = rng.uniform([-3, 0.3, -3], [3, 1.5, 2]).tolist()
        radius, color = float(rng.uniform(0.3, 0.9)), rng.uniform(size=3).tolist()
        sphere = {"center": center, "radius": radius, "color": color}
        if lights and k % 2:
            sphere |= {"specular": [0.5, 0.5, 0.5], "shininess": float(rng.choice([8, 40]))}
        if mirrors and k % 3 == 0:
            sphere |= {"mirror": rng.uniform(0.3, 0.9, size=3).tolist()}
            if glossy and k == 0:  # one glossy, one ideal mirror
                sphere |= {"glossiness": float(rng.uniform(0.1, 0.5))}
        if moving and k % 2 == 0:
            sphere |= {"velocity": rng.uniform([-3, -0.3, -1], [3, 0.3, 1]).tolist()}
        balls.append(sphere)
    data = {
        "version": 2,
        "camera": {"eye": [float(rng.uniform(-1, 1)), 2.5, 8], "lookat": [0, 0.8, 0],
                   "up": [0, 1, 0], "fov_angle": 45, "width": 48, "height": 36},
        "background": rng.uniform(size=3).tolist(),
        "spheres": balls,
        "billboards": [
            {"upper_left": [-6, 0, -6], "upper_right": [6, 0, -6], "lower_left": [-6, 0, 6],
             "color": [0.8, 0.8, 0.78]},
            {"upper_left": [-6, 5, -4], "upper_right": [6, 5, -4], "lower_left": [-6, 0, -4],
             "image": "textures/checker.png"},
        ],
        "render": {"samples_per_pixel": samples, "sampler": sampler,
                   "seed": int(rng.integers(0, 2**32))},
    }  # fmt: skip
    if lights:
        corner = rng.uniform([-2, 4, -1], [0, 5, 1])
        data["lights"] = [
            {"type": "area", "corner": corner.tolist(), "edge1": [float(rng.uniform(1, 3)), 0, 0],
             "edge2": [0, 0, float(rng.uniform(1, 2))], "color": [0.7, 0.7, 0.65]},
            {"type": "point", "position": [3.0, 4.0, 4.0], "color": [0.3, 0.3, 0.35]},
            {"type": "directional", "direction": [-0.3, -1.0, -0.4], "color": [0.2, 0.2, 0.2]},
            {"type": "area", "corner": [-4.0, 0.5, -2.0], "edge1": [0, 2.0, 0],
             "edge2": [0, 0, 3.0], "radiance": [3.0, 2.6, 2.2]},  # lights +x; its back -x
        ]  # fmt: skip
        data["ambient"] = [0.1, 0.1, 0.1]
    if lens:
        data["camera"] |= {"aperture": float(rng.uniform(0.1, 0.6)),
                           "focus_distance": float(rng.uniform(5, 10))}  # fmt: skip
    if mirrors:
        data["max_depth"] = 2
    if moving:
        data["render"]["shutter"] = sorted(rng.uniform(0, 1, size=2).tolist())
    return scene_from_dict(data, folder=SCENES)

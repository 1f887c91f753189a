"""The grading tests: per stage, with points and Gradescope visibility.

Each test names a task of :mod:`raykit_grading.kit.tasks` and builds its inputs from a seed or a
scene file. The expected result is that task run with the reference raykit; the submission's
result is the same task run in the child. Array tests compare every number within the stated
tolerance (a miss may be NaN or inf); image tests compare renders with
:mod:`raykit_grading.kit.compare`.

Inputs are drawn, never fixed: :meth:`GradingTest.inputs` takes a random generator. The
student release ships each visible test's *public* draw (:meth:`GradingTest.public_inputs`,
from a seed of its own) for practice; grading draws others
(:meth:`GradingTest.graded_inputs`) from the assignment's secret seed
(:mod:`raykit_grading.assignment.seeds`), so nothing shipped to students answers a graded test, and
every student and every regrade gets the same tests. Scenes are graded from a camera moved a little
at random (:func:`jitter_camera`: another image size, eye and field of view), arrays from new
random rays, sizes and parameters.

The same seed must give the same inputs on any machine (Gradescope's, of any processor): the
draw uses numpy's generator, elementwise arithmetic, ``np.sqrt`` (correctly rounded) and
:func:`raykit.rays.dot` / :func:`~raykit.rays.normalize` (sums left to right), never ``@``,
``np.dot``, ``np.linalg.norm`` or numpy's vectorised sin/cos, whose last bits depend on BLAS
and the processor's vector width (tests/grading/assignment/test_seeds.py checks both).

Stage 5 (distributed ray tracing) is graded with a fixed seed, not statistically. Its student
functions are pure functions of given uniform numbers (:mod:`raykit.sampling`), so each is
tested exactly on drawn numbers, within the same tolerance as every array test. A render's
numbers come from the renderer's noise (:mod:`raykit.engine.noise`: a hash of the seed, the
pixel, the sample and the dimension), which is given code, not the student's: a correct
submission gets the same numbers, makes the same choices in each pixel, on the lens and on
the lights, and so renders the same picture, noise and all, to within rounding; the image
comparison's tolerance (2 levels, or a neighbour) absorbs what another order of the same
operations changes. A statistical test (mean and variance of the noise) would pass mistakes
that keep the mean, such as samples that are not jittered, and would need many samples: a
fixed seed needs few and names the mistake. Graded draws of a distributed scene take a new
render seed besides the moved camera, so no shipped picture is a graded one.

``visible`` tests show their result at once; ``after_due_date`` tests are hidden until then.
"""

from __future__ import annotations

import json
import math
import zlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from raykit.rays import dot, length, normalize

REPO = Path(__file__).resolve().parents[2]
SCENES = REPO / "scenes"
HIDDEN_SCENES = REPO / "grading" / "hidden-scenes"
VISIBLE, HIDDEN = "visible", "after_due_date"
RTOL, ATOL = 1e-6, 1e-9


@dataclass(frozen=True)
class Callee:
    """A student function that a test's function calls, tested on the same inputs when the
    test fails, to say where the difference starts: ``task`` runs it, on the inputs
    ``inputs(spec, arrays)`` makes from the test's."""

    name: str
    task: str
    inputs: Callable[[dict, dict], tuple[dict, dict]]


LINE_RAYS_CALL = (
    Callee(
        "pixel_x",
        "pixel_x",
        lambda spec, arrays: (
            {"pixels": spec["camera"]["pixels"], "samples": spec.get("samples", 1)},
            {},
        ),
    ),
)
RAYS_THROUGH_CALLS = (
    Callee(
        "camera_frame",
        "camera_frame",
        lambda spec, arrays: ({k: spec["camera"][k] for k in ("eye", "lookat", "up")}, {}),
    ),
    Callee("_in_plane", "in_plane", lambda spec, arrays: (spec, arrays)),
)


@dataclass(frozen=True)
class GradingTest:
    """One graded check. ``inputs(rng)`` gives (spec, arrays, files for the child); ``rng`` is
    None for the public draw of a scene (the scene exactly as in ``scenes/``)."""

    name: str
    stage: str
    points: float
    visibility: str
    task: str
    inputs: Callable[
        [np.random.Generator | None], tuple[dict, dict[str, np.ndarray], dict[str, Path]]
    ]
    kind: str = "arrays"  # or "image"
    tolerance: str = f"each number within rtol {RTOL:g}, atol {ATOL:g}"
    mistakes: bool = False  # diagnose the classic mistakes on this image (arrays: always)
    callees: tuple[Callee, ...] = ()  # the student functions its task's function calls

    @property
    def key(self) -> str:
        """``"3.6"``: the number the test is known by."""
        return self.name.split()[0]

    def public_inputs(self):
        """The practice draw shipped with the student release (always the same)."""
        return self.inputs(None)

    def graded_inputs(self, seed: int):
        """The draw graded under ``seed`` (the assignment's secret seed)."""
        return self.inputs(np.random.default_rng([seed, zlib.crc32(self.name.encode())]))


def _public(rng: np.random.Generator | None, seed: int) -> np.random.Generator:
    return rng if rng is not None else np.random.default_rng(seed)


def _rays(rng, count: int, dims: int, aim: np.ndarray, spread: float):
    origins = rng.uniform(-4, 4, (count, dims))
    targets = aim + rng.uniform(-spread, spread, (count, dims))
    return origins, normalize(targets - origins)


def _split(values: dict):
    spec = {k: v for k, v in values.items() if not isinstance(v, np.ndarray)}
    arrays = {k: v for k, v in values.items() if isinstance(v, np.ndarray)}
    return spec, arrays, {}


def _drawn(seed: int, draw: Callable[[np.random.Generator], dict]):
    """A test whose spec and arrays ``draw`` makes from a generator (``seed`` for the public
    draw)."""
    return lambda rng: _split(draw(_public(rng, seed)))


def _ray_test(seed, count, dims, aim, spread, more: Callable[[np.random.Generator], dict]):
    def draw(rng):
        origins, directions = _rays(rng, count, dims, np.asarray(aim, float), spread)
        return {"origins": origins, "directions": directions, **more(rng)}

    return _drawn(seed, draw)


def jitter_camera(scene: dict, rng: np.random.Generator) -> dict:
    """The scene seen by a camera changed at random, so that no shipped picture is a graded
    one: a different image size (5-15% larger or smaller; a line-scan camera: 1-3 pixels more
    or fewer), the eye moved by 3-6% of its distance to what it looks at (a line-scan camera:
    moved and turned a little), fov_angle changed by 2-5%. The picture stays the scene's, and
    its classic mistakes stay recognisable."""

    def either_way(low: float, high: float) -> float:
        return float(rng.choice([-1.0, 1.0]) * rng.uniform(low, high))

    camera = scene["camera"]
    if "eye" in camera:  # 3D
        eye, lookat = np.array(camera["eye"], float), np.array(camera["lookat"], float)
        away = rng.normal(size=3)
        away *= rng.uniform(0.03, 0.06) * length(eye - lookat) / length(away)
        camera["eye"] = (eye + away).tolist()
        scale = 1 + either_way(0.05, 0.15)
        camera["width"] = max(8, round(camera["width"] * scale))
        camera["height"] = max(8, round(camera["height"] * scale))
    else:  # the 2D line-scan camera
        e, w = np.array(camera["e"], float), np.array(camera["w"], float)
        # turned by up to 1.7 degrees, the angle whose tangent is ``slope``: cos and sin from
        # a square root (correctly rounded everywhere), not from a sin/cos of numpy or libm
        slope = float(rng.uniform(-0.03, 0.03))
        cos, sin = 1 / math.sqrt(1 + slope * slope), slope / math.sqrt(1 + slope * slope)
        camera["e"] = (e + rng.uniform(-0.05, 0.05, 2)).tolist()
        camera["w"] = [float(cos * w[0] - sin * w[1]), float(sin * w[0] + cos * w[1])]
        camera["pixels"] = max(4, camera["pixels"] + int(either_way(1, 4)))
    camera["fov_angle"] = float(camera["fov_angle"] * (1 + either_way(0.02, 0.05)))
    return scene


def _scene_test(
    path: Path, *, width: int | None = None, height: int | None = None, scans: int | None = None
):
    """A scene file (and its textures) for the render, scan and sweep tasks; graded draws see
    it through :func:`jitter_camera`."""

    def build(rng):
        scene = json.loads(path.read_text())
        scene.pop("$schema", None)
        if width:
            scene["camera"]["width"], scene["camera"]["height"] = width, height
        if rng is not None:
            jitter_camera(scene, rng)
            if "render" in scene:  # a distributed render: new noise too (see the module page)
                scene["render"]["seed"] = int(rng.integers(2**31))
        files = {}
        for board in scene.get("billboards", []):
            if "image" in board:
                source = (path.parent / board["image"]).resolve()
                relative = f"scene/textures/{source.name}"
                files[relative] = source
                board["image"] = f"textures/{source.name}"
        spec = {"scene": scene, "folder": "scene"}
        if scans:
            spec["scans"] = scans
        return spec, {}, files

    return build


def _tiny_far_sphere(rng):
    """Rays from the origin at the silhouette of a sphere of radius 1e-3 at distance 1e5."""
    distance = rng.uniform(0.8e5, 1.2e5)
    center = np.array([0.0, 0.0, -distance])
    aim = center + rng.uniform(-1.5e-3, 1.5e-3, (400, 3)) * [1, 1, 0]
    directions = normalize(aim)
    return {"radius": 1e-3, "origins": np.zeros((400, 3)), "directions": directions,
            "center": center}  # fmt: skip


def _line_camera(rng, **kw):
    return {
        "e": (np.array([0.5, -1.0]) + rng.uniform(-0.5, 0.5, 2)).tolist(),
        "w": (np.array([2.0, 1.0]) + rng.uniform(-0.5, 0.5, 2)).tolist(),
        "fov_angle": float(rng.uniform(30, 80)),
        "pixels": int(rng.integers(5, 20)),
        **kw,
    }


def _camera(rng, **kw):
    return {
        "eye": (np.array([1.0, 2.0, 6.0]) + rng.uniform(-1, 1, 3)).tolist(),
        "lookat": (np.array([0.0, 0.5, 0.0]) + rng.uniform(-0.5, 0.5, 3)).tolist(),
        "up": (np.array([0.2, 1.0, 0.1]) + rng.uniform(-0.2, 0.2, 3)).tolist(),
        "fov_angle": float(rng.uniform(25, 70)),
        "width": int(rng.integers(9, 20)),
        "height": int(rng.integers(7, 15)),
        **kw,
    }


def _unit_rows(rng, count):
    return normalize(rng.normal(size=(count, 3)))


def _shading_arrays(seed: int, *names: str):
    """Random inputs of the shading terms: colours, intensity, unit vectors, exponents."""

    def draw(rng):
        count = 300
        made = {
            "kd": rng.uniform(0, 1, (count, 3)),
            "ks": rng.uniform(0, 1, (count, 3)),
            "intensity": rng.uniform(0, 1.5, 3),
            "n": _unit_rows(rng, count),
            "l": _unit_rows(rng, count),
            "v": _unit_rows(rng, count),
            "p": rng.uniform(1, 200, count),
            "d": _unit_rows(rng, count),
        }
        return {k: made[k] for k in names}

    return _drawn(seed, draw)


def _sphere_points(rng):
    center, radius = rng.uniform(-3, 3, 3), float(rng.uniform(0.5, 3))
    return {"radius": radius, "points": center + radius * _unit_rows(rng, 200), "center": center}


def _parallel_planes(rng):
    """Rays parallel to a plane (some in it), and planes behind the ray."""
    n = normalize(rng.normal(size=3))
    a = rng.uniform(-1, 1, 3)
    along = normalize(np.cross(n, rng.normal(size=3)))
    above = a + n * rng.uniform(0.5, 2)
    origins = np.array([above, above, above, a - n, a])  # the last starts on the plane: t = 0
    directions = np.array([along, n, -n, -n, -n])
    return {"origins": origins, "directions": directions, "a": a, "n": n}


def _plane_sides(rng):
    """Whole-number points and normal, so p·n > a·n is decided exactly however it is computed;
    a third of the points lie on the plane."""
    n = rng.integers(-3, 4, 3).astype(float)
    n[0] = n[0] or 1.0
    a = rng.integers(-3, 4, 3).astype(float)
    p = rng.integers(-5, 6, (90, 3)).astype(float)
    on = p[:30].copy()
    on[:, 0] = a[0] - dot(on[:, 1:] - a[1:], n[1:]) / n[0]  # solved for x: on the plane
    keep = on[:, 0] == np.round(on[:, 0])  # whole numbers only
    return {"p": np.vstack([on[keep], p[30:]]), "a": a, "n": n}


def _pixel_points(rng, camera: dict) -> dict:
    count = 27
    return {
        "camera": camera,
        "x": rng.uniform(0, camera["width"], count),
        "y": rng.uniform(0, camera["height"], count),
    }


def _shadow_test(rng: np.random.Generator):
    """Points on a tilted floor near 1e6 (as a renderer finds them, with their rounding) under a
    point light, some behind a ball: the shadow test must find the ball and nothing else."""
    from raykit.planes import hit_plane
    from raykit.rays import point_at

    far = np.array([1e6, 1e6, 1e6])
    eye = far + [0.0, 4.0, 6.0]
    aim = far + np.column_stack([rng.uniform(-3, 3, 400), np.zeros(400), rng.uniform(-3, 3, 400)])
    directions = normalize(aim - eye)
    origins = np.broadcast_to(eye, directions.shape).copy()
    across, along = np.array([1.0, 0.1, 0.0]), np.array([0.0, 0.2, 1.0])  # the floor's edges
    normal = normalize(np.cross(along, across))
    t = hit_plane(origins, directions, far, normal)
    points = point_at(origins, directions, t)
    light = far + [0.5, 5.0, 0.2] + rng.uniform(-0.3, 0.3, 3)
    to_light = light - points
    distance = np.sqrt(dot(to_light, to_light))
    floor = {
        "upper_left": (far - 10 * across - 10 * along).tolist(),
        "lower_left": (far - 10 * across + 10 * along).tolist(),
        "upper_right": (far + 10 * across - 10 * along).tolist(),
        "color": [0.5, 0.5, 0.5],
    }
    scene = {
        "camera": {
            "eye": eye.tolist(),
            "lookat": far.tolist(),
            "up": [0, 1, 0],
            "fov_angle": 60,
            "width": 4,
            "height": 4,
        },
        "spheres": [
            {"center": (far + [0.3, 2.0, 0.1]).tolist(), "radius": 0.8, "color": [1, 0, 0]}
        ],
        "billboards": [floor],
    }
    return {
        "scene": scene,
        "points": points,
        "normals": np.tile(normal, (len(points), 1)),
        "error": np.finfo(float).eps * (np.abs(origins).max(axis=1) + t),
        "l": to_light / distance[:, None],
        "distance": distance,
    }


def _uniforms(rng, count: int) -> np.ndarray:
    """Uniform numbers ``(count, 2)`` in [0, 1), a few of them exactly 0 (the square's edge)."""
    values = rng.uniform(0, 1, (count, 2))
    values[rng.uniform(0, 1, (count, 2)) < 0.05] = 0.0
    return values


def _in_pixels(rng):
    count, width, height = 60, int(rng.integers(4, 30)), int(rng.integers(4, 30))
    return {
        "rows": rng.integers(0, height, count),
        "cols": rng.integers(0, width, count),
        "uniforms": _uniforms(rng, count),
    }


def _jittered_set(rng):
    n = int(rng.integers(2, 7))
    return {"n": n, "uniforms": _uniforms(rng, n * n)}


def _jittered_cells(rng):
    """Points in cells in any order, as the renderer's shuffled pairs ask for them."""
    n = int(rng.integers(2, 7))
    cells = np.concatenate([rng.permutation(n * n) for _ in range(3)])
    return {"n": n, "cells": cells, "uniforms": _uniforms(rng, len(cells))}


def _parallelogram(rng, **more):
    return {
        "corner": rng.uniform(-3, 3, 3),
        "edge1": rng.uniform(-2, 2, 3),
        "edge2": rng.uniform(-2, 2, 3),
        "uniforms": _uniforms(rng, 80),
        **more,
    }


def _disk_edges(rng):
    """The concentric map where it changes quarters or divides by zero: the centre, the
    square's diagonals (|a| = |b|), its edges and the lines a = 0 and b = 0 through the
    centre, with random numbers between."""
    t = np.append(rng.uniform(0, 1, 12), [0.0, 0.25, 0.5, 0.75])
    half = np.full_like(t, 0.5)
    zero = np.zeros_like(t)
    special = np.vstack([
        np.column_stack([t, t]), np.column_stack([t, 1 - t]),  # the diagonals
        np.column_stack([t, zero]), np.column_stack([zero, t]),  # two edges of the square
        np.column_stack([t, half]), np.column_stack([half, t]),  # a = 0 or b = 0
    ])  # fmt: skip
    return {"uniforms": np.vstack([special, _uniforms(rng, 40)])}


def _lens(rng):
    from raykit.camera import camera_frame

    camera = _camera(rng)
    u, v, _ = camera_frame(*(np.array(camera[k], float) for k in ("eye", "lookat", "up")))
    return {
        "eye": np.array(camera["eye"]),
        "u": u,
        "v": v,
        "aperture": float(rng.uniform(0.05, 1.0)),
        "uniforms": _uniforms(rng, 60),
    }


def _thin_lens(rng):
    camera = _camera(
        rng, aperture=float(rng.uniform(0.05, 1.0)), focus_distance=float(rng.uniform(2, 12))
    )
    points = _pixel_points(rng, camera)
    return {**points, "uniforms": _uniforms(rng, len(points["x"]))}


def _directions_to_perturb(rng):
    """Rows r of any length, and some whose components tie in magnitude (the basis takes the
    first of equals) or are zero."""
    ties = np.array([[1.0, 1.0, 1.0], [2.0, -2.0, 5.0], [0.0, 0.0, 3.0], [-1.0, 0.0, 0.0],
                     [0.0, -4.0, 4.0], [3.0, 1.0, -1.0]])  # fmt: skip
    return np.vstack([ties, rng.normal(size=(60, 3)) * rng.uniform(0.2, 5, (60, 1))])


def _glossy_bounces(rng):
    """Rays d arriving at surfaces n (d·n < 0), glossy mirrors of each row's own glossiness a,
    a sixth of them ideal (a = 0)."""
    n = _unit_rows(rng, 90)
    d = _unit_rows(rng, 90)
    d = np.where((dot(d, n) > 0)[:, None], -d, d)
    a = rng.uniform(0.02, 0.8, 90)
    a[rng.uniform(0, 1, 90) < 1 / 6] = 0.0
    return {"d": d, "n": n, "a": a, "uniforms": _uniforms(rng, 90)}


def _shutter(rng):
    start = float(rng.uniform(0, 2))
    return {
        "open": start,
        "close": start + float(rng.uniform(0.1, 3)),
        "uniforms": rng.uniform(0, 1, (int(rng.integers(3, 30)), int(rng.integers(2, 26)))),
    }


def _moving_sphere(rng):
    return {
        "center": rng.uniform(-3, 3, 3),
        "velocity": rng.uniform(-2, 2, 3),
        "times": rng.uniform(0, 2, 70),
    }


STAGE1, STAGE2, STAGE3 = "1 line-scan camera", "2 rays, planes and spheres", "3 renderer"
STAGE4 = "4 shading, shadows and mirrors"
STAGE5 = "5 distributed ray tracing"

TESTS = [
    GradingTest(
        "1.1 pixel positions x_i",
        STAGE1, 1, VISIBLE, "pixel_x",
        _drawn(11, lambda rng: {"pixels": int(rng.integers(5, 40))}),
    ),
    GradingTest(
        "1.2 pixel positions with several samples per pixel",
        STAGE1, 1, HIDDEN, "pixel_x",
        _drawn(12, lambda rng: {"pixels": int(rng.integers(8, 40)),
                                "samples": int(rng.integers(2, 5))}),
    ),
    GradingTest(
        "1.3 perspective rays of the line-scan camera",
        STAGE1, 2, VISIBLE, "line_rays",
        _drawn(13, lambda rng: {"camera": _line_camera(rng)}),
        callees=LINE_RAYS_CALL,
    ),
    GradingTest(
        "1.4 orthographic rays of the line-scan camera",
        STAGE1, 1, HIDDEN, "line_rays",
        _drawn(14, lambda rng: {"camera": _line_camera(
            rng, projection="orthographic", width=float(rng.uniform(1, 4)))}),
        callees=LINE_RAYS_CALL,
    ),
    GradingTest(
        "1.5 ray-segment hits: t and s",
        STAGE1, 2, VISIBLE, "hit_segment",
        _ray_test(15, 400, 2, [1.0, 1.0], 3.0, lambda rng: {
            "start": (np.array([0.0, 2.0]) + rng.uniform(-0.5, 0.5, 2)).tolist(),
            "end": (np.array([2.5, -0.5]) + rng.uniform(-0.5, 0.5, 2)).tolist()}),
    ),
    GradingTest(
        "1.6 one scan of scenes/linescan/slide.json",
        STAGE1, 2, VISIBLE, "scan",
        _scene_test(SCENES / "linescan/slide.json"),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "1.7 a sweep of scenes/linescan/conveyor_small.json",
        STAGE1, 2, HIDDEN, "sweep",
        _scene_test(SCENES / "linescan/conveyor_small.json", scans=160),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "2.1 ray-plane hits",
        STAGE2, 2, VISIBLE, "hit_plane",
        _ray_test(21, 500, 3, [0.0, 0.0, 0.0], 5.0, lambda rng: {
            "a": rng.uniform(-1, 1, 3), "n": rng.normal(size=3)}),
    ),
    GradingTest(
        "2.2 ray-plane: rays parallel to the plane and planes behind the ray",
        STAGE2, 1, HIDDEN, "hit_plane",
        _drawn(22, lambda rng: _parallel_planes(rng)),
    ),
    GradingTest(
        "2.3 ray-sphere hits",
        STAGE2, 2, VISIBLE, "hit_sphere",
        _ray_test(23, 500, 3, [0.5, 0.0, -1.0], 2.5, lambda rng: {
            "center": np.array([0.5, 0, -1.0]) + rng.uniform(-0.5, 0.5, 3),
            "radius": float(rng.uniform(0.8, 1.8))}),
    ),
    GradingTest(
        "2.4 ray-sphere from inside the sphere",
        STAGE2, 1, HIDDEN, "hit_sphere",
        _ray_test(24, 200, 3, [0.0, 0.0, 0.0], 9.0, lambda rng: {
            "center": rng.uniform(-0.5, 0.5, 3), "radius": float(rng.uniform(8, 10))}),
    ),
    GradingTest(
        "2.5 ray-sphere: a tiny sphere far away (the discriminant's lost digits)",
        STAGE2, 2, HIDDEN, "hit_sphere",
        _drawn(25, _tiny_far_sphere),
    ),
    GradingTest(
        "2.6 which side of a plane points are on: front, on, behind",
        STAGE2, 1, VISIBLE, "plane_side",
        _drawn(26, lambda rng: _plane_sides(rng)),
    ),
    GradingTest(
        "2.7 the normal of a plane through three points (not normalized)",
        STAGE2, 1, VISIBLE, "normal_from_points",
        _drawn(27, lambda rng: {k: rng.uniform(-3, 3, (100, 3)) for k in ("a", "p", "q")}),
    ),
    GradingTest(
        "3.1 the camera frame u, v, w",
        STAGE3, 1, VISIBLE, "camera_frame",
        _drawn(31, lambda rng: {k: v for k, v in _camera(rng).items()
                                if k in ("eye", "lookat", "up")}),
    ),
    GradingTest(
        "3.2 perspective rays through pixel points",
        STAGE3, 2, VISIBLE, "rays_through",
        _drawn(32, lambda rng: _pixel_points(rng, _camera(rng))),
        callees=RAYS_THROUGH_CALLS,
    ),
    GradingTest(
        "3.3 orthographic rays through pixel points",
        STAGE3, 1, HIDDEN, "rays_through",
        _drawn(33, lambda rng: _pixel_points(rng, _camera(rng, projection="orthographic"))),
        callees=RAYS_THROUGH_CALLS,
    ),
    GradingTest(
        "3.4 ray-billboard hits: t, alpha, beta",
        STAGE3, 2, VISIBLE, "hit_billboard",
        _ray_test(34, 500, 3, [0.5, 0.5, 0.0], 2.0, lambda rng: {
            "upper_left": (np.array([-0.5, 1.5, 0.2]) + rng.uniform(-0.3, 0.3, 3)).tolist(),
            "lower_left": (np.array([-0.3, -0.5, -0.1]) + rng.uniform(-0.3, 0.3, 3)).tolist(),
            "upper_right": (np.array([1.8, 1.4, 0.4]) + rng.uniform(-0.3, 0.3, 3)).tolist()}),
    ),
    GradingTest(
        "3.5 nearest texel of (alpha, beta)",
        STAGE3, 1, VISIBLE, "texel_indices",
        _drawn(35, lambda rng: {
            "alpha": np.append(rng.uniform(0, 1, 40), [0.0, 1.0]),
            "beta": np.append(rng.uniform(0, 1, 40), [1.0, 0.0]),
            "width": int(rng.integers(3, 12)), "height": int(rng.integers(3, 12))}),
    ),
    GradingTest(
        "3.6 render scenes/classic.json (320 x 240)",
        STAGE3, 4, VISIBLE, "render",
        _scene_test(SCENES / "classic.json", width=320, height=240),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "3.7 render scenes/cutouts.json",
        STAGE3, 3, VISIBLE, "render",
        _scene_test(SCENES / "cutouts.json", width=240, height=160),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "3.8 render scenes/orthographic.json",
        STAGE3, 2, HIDDEN, "render",
        _scene_test(SCENES / "orthographic.json", width=200, height=200),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "3.9 render scenes/wide_fov.json",
        STAGE3, 2, HIDDEN, "render",
        _scene_test(SCENES / "wide_fov.json", width=300, height=150),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "3.10 render a hidden scene: odd size, tilted up, inside a sphere",
        STAGE3, 3, HIDDEN, "render",
        _scene_test(HIDDEN_SCENES / "odd.json"),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "3.11 render a hidden scene: balls into each other, a wall through a ball",
        STAGE3, 3, HIDDEN, "render",
        _scene_test(HIDDEN_SCENES / "overlaps.json"),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "4.1 sphere normals", STAGE4, 1, VISIBLE, "sphere_normals", _drawn(41, _sphere_points)
    ),
    GradingTest(
        "4.2 toward a point light: l and distance",
        STAGE4, 1, VISIBLE, "toward_light",
        _drawn(42, lambda rng: {"position": rng.uniform(-2, 5, 3).tolist(),
                                "points": rng.uniform(-3, 3, (50, 3))}),
    ),
    GradingTest(
        "4.3 toward a directional light",
        STAGE4, 1, HIDDEN, "toward_light",
        _drawn(43, lambda rng: {"direction": rng.normal(size=3).tolist(),
                                "points": rng.uniform(-3, 3, (50, 3))}),
    ),
    GradingTest(
        "4.4 Lambert's diffuse term",
        STAGE4, 2, VISIBLE, "lambert",
        _shading_arrays(44, "kd", "intensity", "n", "l"),
    ),
    GradingTest(
        "4.5 Blinn-Phong's highlight",
        STAGE4, 2, VISIBLE, "blinn_phong",
        _shading_arrays(45, "ks", "intensity", "n", "l", "v", "p"),
    ),
    GradingTest(
        "4.6 mirror directions", STAGE4, 1, VISIBLE, "reflect", _shading_arrays(46, "d", "n")
    ),
    GradingTest(
        "4.7 the shadow test on a floor at 1e6 (shadow acne)",
        STAGE4, 2, HIDDEN, "in_shadow",
        _drawn(47, _shadow_test),
    ),
    GradingTest(
        "4.8 render scenes/classic_lit.json (320 x 240)",
        STAGE4, 4, VISIBLE, "render",
        _scene_test(SCENES / "classic_lit.json", width=320, height=240),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "4.9 render scenes/shadow_on_billboard.json",
        STAGE4, 3, VISIBLE, "render",
        _scene_test(SCENES / "shadow_on_billboard.json", width=240, height=180),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "4.10 render scenes/mirror_balls.json",
        STAGE4, 3, HIDDEN, "render",
        _scene_test(SCENES / "mirror_balls.json", width=240, height=150),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "4.11 render a hidden lit scene at 1e6, a ball touching the floor",
        STAGE4, 3, HIDDEN, "render",
        _scene_test(HIDDEN_SCENES / "lit_far.json"),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "5.1 a point in each pixel from uniform numbers",
        STAGE5, 1, VISIBLE, "point_in_pixel", _drawn(51, _in_pixels),
    ),
    GradingTest(
        "5.2 the random sample set",
        STAGE5, 1, VISIBLE, "random_set",
        _drawn(52, lambda rng: {"uniforms": _uniforms(rng, int(rng.integers(4, 40)))}),
    ),
    GradingTest(
        "5.3 the jittered sample set of n x n",
        STAGE5, 2, VISIBLE, "jittered_set", _drawn(53, _jittered_set),
    ),
    GradingTest(
        "5.4 jittered points in cells in any order",
        STAGE5, 1, HIDDEN, "jittered_point", _drawn(54, _jittered_cells),
    ),
    GradingTest(
        "5.5 points on a parallelogram (an area light)",
        STAGE5, 1, VISIBLE, "point_on_parallelogram", _drawn(55, _parallelogram),
    ),
    GradingTest(
        "5.6 an area light sampled as point lights",
        STAGE5, 1, HIDDEN, "sampled",
        _drawn(56, lambda rng: _parallelogram(rng, color=rng.uniform(0, 1.5, 3))),
    ),
    GradingTest(
        "5.7 points on the unit disk (the concentric map)",
        STAGE5, 2, VISIBLE, "point_on_disk",
        _drawn(57, lambda rng: {"uniforms": _uniforms(rng, 100)}),
    ),
    GradingTest(
        "5.8 the concentric map on the square's diagonals, edges and centre",
        STAGE5, 1, HIDDEN, "point_on_disk", _drawn(58, _disk_edges),
    ),
    GradingTest(
        "5.9 points on the thin lens",
        STAGE5, 1, VISIBLE, "point_on_lens", _drawn(59, _lens),
    ),
    GradingTest(
        "5.10 thin-lens rays through pixel points",
        STAGE5, 2, VISIBLE, "thin_lens_rays", _drawn(510, _thin_lens),
        callees=RAYS_THROUGH_CALLS,
    ),
    GradingTest(
        "5.11 an orthonormal basis around a direction",
        STAGE5, 1, VISIBLE, "basis_around",
        _drawn(511, lambda rng: {"r": _directions_to_perturb(rng)}),
    ),
    GradingTest(
        "5.12 perturbed directions (glossy reflection)",
        STAGE5, 2, VISIBLE, "perturbed_direction",
        _drawn(512, lambda rng: {"r": normalize(_directions_to_perturb(rng)),
                                 "a": float(rng.uniform(0.05, 0.6)),
                                 "uniforms": _uniforms(rng, 66)}),
        callees=(Callee("basis_around", "basis_around", lambda spec, arrays: (
            {}, {"r": arrays["r"]})),),
    ),
    GradingTest(
        "5.13 glossy mirror directions, and which leave above the surface",
        STAGE5, 2, VISIBLE, "glossy_reflect", _drawn(513, _glossy_bounces),
        callees=(Callee("reflect", "reflect", lambda spec, arrays: (
            {}, {"d": arrays["d"], "n": arrays["n"]})),),
    ),
    GradingTest(
        "5.14 a time in the shutter interval for every ray",
        STAGE5, 1, VISIBLE, "shutter_times", _drawn(514, _shutter),
    ),
    GradingTest(
        "5.15 a moving sphere's centre at each ray's time",
        STAGE5, 1, VISIBLE, "center_at", _drawn(515, _moving_sphere),
    ),
    GradingTest(
        "5.16 render scenes/soft_shadows.json (an area light)",
        STAGE5, 3, VISIBLE, "render",
        _scene_test(SCENES / "soft_shadows.json", width=128, height=96),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "5.17 render scenes/depth_of_field.json (a thin lens)",
        STAGE5, 3, VISIBLE, "render",
        _scene_test(SCENES / "depth_of_field.json", width=128, height=96),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "5.18 render scenes/glossy.json (glossy mirrors)",
        STAGE5, 3, VISIBLE, "render",
        _scene_test(SCENES / "glossy.json", width=96, height=72),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "5.19 render scenes/motion_blur.json (a moving sphere)",
        STAGE5, 3, HIDDEN, "render",
        _scene_test(SCENES / "motion_blur.json", width=96, height=72),
        kind="image", mistakes=True,
    ),
    GradingTest(
        "5.20 render a hidden scene: a tilted area light seen through a lens, random samples",
        STAGE5, 3, HIDDEN, "render",
        _scene_test(HIDDEN_SCENES / "lens_and_panel.json"),
        kind="image", mistakes=True,
    ),
]  # fmt: skip


def by_name(names: list[str] | None) -> list[GradingTest]:
    """The tests whose numbers or names start with any of ``names`` (all when None)."""
    if not names:
        return list(TESTS)

    def chosen(test: GradingTest, name: str) -> bool:
        if name.replace(".", "").isdigit():  # a number: that test ("3.1" is not "3.10")
            return test.key == name
        return test.name.startswith(name)

    return [t for t in TESTS if any(chosen(t, n) for n in names)]


def listing(tests: list[GradingTest] | None = None) -> str:
    """The tests as ``python -m raykit_grading tests`` prints them: a heading per stage with
    its points, each test's points, visibility and name, and the totals."""
    tests = list(TESTS if tests is None else tests)
    lines = []
    for stage in dict.fromkeys(t.stage for t in tests):
        mine = [t for t in tests if t.stage == stage]
        hidden = sum(t.visibility != VISIBLE for t in mine)
        lines.append(
            f"Stage {stage}: {len(mine)} tests ({hidden} hidden), "
            f"{sum(t.points for t in mine):g} points"
        )
        lines += [f"  {t.points:>4g}  {t.visibility:<15} {t.name}" for t in mine]
        lines.append("")
    hidden = [t for t in tests if t.visibility != VISIBLE]
    lines.append(
        f"Total: {len(tests)} tests, {sum(t.points for t in tests):g} points; hidden until the "
        f"due date: {len(hidden)} tests, {sum(t.points for t in hidden):g} points"
    )
    return "\n".join(lines)

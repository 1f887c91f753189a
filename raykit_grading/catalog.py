"""The grading tests: per stage, with points and Gradescope visibility.

Each test names a task of :mod:`raykit_grading.child` and builds its inputs from a seed or a
scene file. The expected result is that task run with the reference raykit; the submission's
result is the same task run in the child. Array tests compare every number within the stated
tolerance (a miss may be NaN or inf); image tests compare renders with
:mod:`raykit_grading.compare`.

``visible`` tests show their result at once (and ship with the student release);
``after_due_date`` tests are hidden until then.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "scenes"
HIDDEN_SCENES = REPO / "grading-scenes"
VISIBLE, HIDDEN = "visible", "after_due_date"
RTOL, ATOL = 1e-6, 1e-9


@dataclass(frozen=True)
class GradingTest:
    """One graded check. ``inputs()`` gives (spec, arrays, files for the child)."""

    name: str
    stage: str
    points: float
    visibility: str
    task: str
    inputs: Callable[[], tuple[dict, dict[str, np.ndarray], dict[str, Path]]]
    kind: str = "arrays"  # or "image"
    tolerance: str = f"each number within rtol {RTOL:g}, atol {ATOL:g}"
    mistakes: bool = False  # diagnose the classic 3D mistakes on this image


def _rays(seed: int, count: int, dims: int, aim: np.ndarray, spread: float):
    rng = np.random.default_rng(seed)
    origins = rng.uniform(-4, 4, (count, dims))
    targets = aim + rng.uniform(-spread, spread, (count, dims))
    directions = targets - origins
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return origins, directions


def _arrays(**spec_and_arrays):
    def build():
        spec = {k: v for k, v in spec_and_arrays.items() if not isinstance(v, np.ndarray)}
        arrays = {k: v for k, v in spec_and_arrays.items() if isinstance(v, np.ndarray)}
        return spec, arrays, {}

    return build


def _ray_test(seed, count, dims, aim, spread, **more):
    def build():
        origins, directions = _rays(seed, count, dims, np.asarray(aim, float), spread)
        spec = {key: v for key, v in more.items() if not isinstance(v, np.ndarray)}
        arrays = {key: v for key, v in more.items() if isinstance(v, np.ndarray)}
        return spec, {"origins": origins, "directions": directions, **arrays}, {}

    return build


def _scene_test(
    path: Path, *, width: int | None = None, height: int | None = None, scans: int | None = None
):
    """A scene file (and its textures) for the render, scan and sweep tasks."""

    def build():
        scene = json.loads(path.read_text())
        scene.pop("$schema", None)
        if width:
            scene["camera"]["width"], scene["camera"]["height"] = width, height
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


def _tiny_far_sphere(seed: int):
    """Rays from the origin at the silhouette of a sphere of radius 1e-3 at distance 1e5."""
    center = np.array([0.0, 0.0, -1e5])
    rng = np.random.default_rng(seed)
    aim = center + rng.uniform(-1.5e-3, 1.5e-3, (400, 3)) * [1, 1, 0]
    directions = aim / np.linalg.norm(aim, axis=1, keepdims=True)
    return (
        {"radius": 1e-3},
        {"origins": np.zeros((400, 3)), "directions": directions, "center": center},
        {},
    )


def _line_camera(**kw):
    return {"e": [0.5, -1.0], "w": [2.0, 1.0], "fov_angle": 50.0, "pixels": 9, **kw}


def _camera(**kw):
    return {
        "eye": [1.0, 2.0, 6.0],
        "lookat": [0.0, 0.5, 0.0],
        "up": [0.2, 1.0, 0.1],
        "fov_angle": 40.0,
        "width": 13,
        "height": 9,
        **kw,
    }


def _unit_rows(rng, count):
    rows = rng.normal(size=(count, 3))
    return rows / np.linalg.norm(rows, axis=1, keepdims=True)


def _shading_arrays(seed: int, *names: str):
    """Random inputs of the shading terms: colours, intensity, unit vectors, exponents."""

    def build():
        rng = np.random.default_rng(seed)
        count = 300
        n = _unit_rows(rng, count)
        made = {
            "kd": rng.uniform(0, 1, (count, 3)),
            "ks": rng.uniform(0, 1, (count, 3)),
            "intensity": rng.uniform(0, 1.5, 3),
            "n": n,
            "l": _unit_rows(rng, count),
            "v": _unit_rows(rng, count),
            "p": rng.uniform(1, 200, count),
            "d": _unit_rows(rng, count),
        }
        return {}, {k: made[k] for k in names}, {}

    return build


def _sphere_points(seed: int):
    rng = np.random.default_rng(seed)
    center, radius = np.array([1.0, 2.0, -3.0]), 2.5
    return (
        {"radius": radius},
        {"points": center + radius * _unit_rows(rng, 200), "center": center},
        {},
    )


def _shadow_test(seed: int):
    """Points on a tilted floor near 1e6 (as a renderer finds them, with their rounding) under a
    point light, some behind a ball: the shadow test must find the ball and nothing else."""
    from raykit.planes import hit_plane
    from raykit.rays import point_at

    rng = np.random.default_rng(seed)
    far = np.array([1e6, 1e6, 1e6])
    eye = far + [0.0, 4.0, 6.0]
    aim = far + np.column_stack([rng.uniform(-3, 3, 400), np.zeros(400), rng.uniform(-3, 3, 400)])
    directions = (aim - eye) / np.linalg.norm(aim - eye, axis=1, keepdims=True)
    origins = np.broadcast_to(eye, directions.shape).copy()
    across, along = np.array([1.0, 0.1, 0.0]), np.array([0.0, 0.2, 1.0])  # the floor's edges
    normal = np.cross(along, across)
    normal /= np.linalg.norm(normal)
    t = hit_plane(origins, directions, far, normal)
    points = point_at(origins, directions, t)
    light = far + [0.5, 5.0, 0.2]
    to_light = light - points
    distance = np.linalg.norm(to_light, axis=1)
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
    return (
        {"scene": scene},
        {
            "points": points,
            "normals": np.tile(normal, (len(points), 1)),
            "error": np.finfo(float).eps * (np.abs(origins).max(axis=1) + t),
            "l": to_light / distance[:, None],
            "distance": distance,
        },
        {},
    )


STAGE1, STAGE2, STAGE3 = "1 line-scan camera", "2 rays, planes and spheres", "3 renderer"
STAGE4 = "4 shading, shadows and mirrors"

TESTS = [
    GradingTest("1.1 pixel positions x_i, N = 7", STAGE1, 1, VISIBLE, "pixel_x", _arrays(pixels=7)),
    GradingTest(
        "1.2 pixel positions with 3 samples per pixel, N = 16",
        STAGE1,
        1,
        HIDDEN,
        "pixel_x",
        _arrays(pixels=16, samples=3),
    ),
    GradingTest(
        "1.3 perspective rays of the line-scan camera",
        STAGE1,
        2,
        VISIBLE,
        "line_rays",
        _arrays(camera=_line_camera()),
    ),
    GradingTest(
        "1.4 orthographic rays of the line-scan camera",
        STAGE1,
        1,
        HIDDEN,
        "line_rays",
        _arrays(camera=_line_camera(projection="orthographic", width=3.0, pixels=11)),
    ),
    GradingTest(
        "1.5 ray-segment hits: t and s",
        STAGE1,
        2,
        VISIBLE,
        "hit_segment",
        _ray_test(11, 400, 2, [1.0, 1.0], 3.0, start=[0.0, 2.0], end=[2.5, -0.5]),
    ),
    GradingTest(
        "1.6 one scan of scenes/linescan/slide.json",
        STAGE1,
        2,
        VISIBLE,
        "scan",
        _scene_test(SCENES / "linescan/slide.json"),
        kind="image",
    ),
    GradingTest(
        "1.7 a sweep of scenes/linescan/conveyor.json",
        STAGE1,
        2,
        HIDDEN,
        "sweep",
        _scene_test(SCENES / "linescan/conveyor.json", scans=160),
        kind="image",
    ),
    GradingTest(
        "2.1 ray-plane hits",
        STAGE2,
        2,
        VISIBLE,
        "hit_plane",
        _ray_test(
            21,
            500,
            3,
            [0.0, 0.0, 0.0],
            5.0,
            a=np.array([0.3, -0.2, 0.5]),
            n=np.array([0.2, 1.0, -0.4]),
        ),
    ),
    GradingTest(
        "2.2 ray-plane: rays parallel to the plane and planes behind the ray",
        STAGE2,
        1,
        HIDDEN,
        "hit_plane",
        _arrays(
            origins=np.array([[0, 1, 0], [0, 1, 0], [0, 1, 0], [0, 0, 0]], float),
            directions=np.array([[1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 1, 0]], float),
            a=np.zeros(3),
            n=np.array([0.0, 1.0, 0.0]),
        ),
    ),
    GradingTest(
        "2.3 ray-sphere hits",
        STAGE2,
        2,
        VISIBLE,
        "hit_sphere",
        _ray_test(23, 500, 3, [0.5, 0.0, -1.0], 2.5, center=np.array([0.5, 0, -1.0]), radius=1.3),
    ),
    GradingTest(
        "2.4 ray-sphere from inside the sphere",
        STAGE2,
        1,
        HIDDEN,
        "hit_sphere",
        _ray_test(24, 200, 3, [0.0, 0.0, 0.0], 9.0, center=np.zeros(3), radius=9.0),
    ),
    GradingTest(
        "2.5 ray-sphere: a tiny sphere far away (the discriminant's lost digits)",
        STAGE2,
        2,
        HIDDEN,
        "hit_sphere",
        lambda: _tiny_far_sphere(25),
    ),
    GradingTest(
        "3.1 the camera frame u, v, w",
        STAGE3,
        1,
        VISIBLE,
        "camera_frame",
        _arrays(eye=[1.0, 2.0, 6.0], lookat=[0.0, 0.5, 0.0], up=[0.2, 1.0, 0.1]),
    ),
    GradingTest(
        "3.2 perspective rays through pixel points",
        STAGE3,
        2,
        VISIBLE,
        "rays_through",
        lambda: (
            {"camera": _camera()},
            {"x": np.linspace(0, 13, 27), "y": np.linspace(9, 0, 27)},
            {},
        ),
    ),
    GradingTest(
        "3.3 orthographic rays through pixel points",
        STAGE3,
        1,
        HIDDEN,
        "rays_through",
        lambda: (
            {"camera": _camera(projection="orthographic")},
            {"x": np.linspace(0.5, 12.5, 13), "y": np.linspace(0.5, 8.5, 13)},
            {},
        ),
    ),
    GradingTest(
        "3.4 ray-billboard hits: t, alpha, beta",
        STAGE3,
        2,
        VISIBLE,
        "hit_billboard",
        _ray_test(
            34,
            500,
            3,
            [0.5, 0.5, 0.0],
            2.0,
            upper_left=[-0.5, 1.5, 0.2],
            lower_left=[-0.3, -0.5, -0.1],
            upper_right=[1.8, 1.4, 0.4],
        ),
    ),
    GradingTest(
        "3.5 nearest texel of (alpha, beta)",
        STAGE3,
        1,
        VISIBLE,
        "texel_indices",
        _arrays(alpha=np.linspace(0, 1, 41), beta=np.linspace(1, 0, 41), width=7, height=5),
    ),
    GradingTest(
        "3.6 render scenes/classic.json (320 x 240)",
        STAGE3,
        4,
        VISIBLE,
        "render",
        _scene_test(SCENES / "classic.json", width=320, height=240),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "3.7 render scenes/cutouts.json",
        STAGE3,
        3,
        VISIBLE,
        "render",
        _scene_test(SCENES / "cutouts.json", width=240, height=160),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "3.8 render scenes/orthographic.json",
        STAGE3,
        2,
        HIDDEN,
        "render",
        _scene_test(SCENES / "orthographic.json", width=200, height=200),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "3.9 render scenes/wide_fov.json",
        STAGE3,
        2,
        HIDDEN,
        "render",
        _scene_test(SCENES / "wide_fov.json", width=300, height=150),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "3.10 render a hidden scene: odd size, tilted up, inside a sphere",
        STAGE3,
        3,
        HIDDEN,
        "render",
        _scene_test(HIDDEN_SCENES / "odd.json"),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "3.11 render a hidden scene: balls into each other, a wall through a ball",
        STAGE3,
        3,
        HIDDEN,
        "render",
        _scene_test(HIDDEN_SCENES / "overlaps.json"),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "4.1 sphere normals", STAGE4, 1, VISIBLE, "sphere_normals", lambda: _sphere_points(41)
    ),
    GradingTest(
        "4.2 toward a point light: l and distance",
        STAGE4,
        1,
        VISIBLE,
        "toward_light",
        _arrays(
            position=[0.5, 4.0, -1.0], points=np.random.default_rng(42).uniform(-3, 3, (50, 3))
        ),
    ),
    GradingTest(
        "4.3 toward a directional light",
        STAGE4,
        1,
        HIDDEN,
        "toward_light",
        _arrays(
            direction=[1.0, -2.0, 0.5], points=np.random.default_rng(43).uniform(-3, 3, (50, 3))
        ),
    ),
    GradingTest(
        "4.4 Lambert's diffuse term",
        STAGE4,
        2,
        VISIBLE,
        "lambert",
        _shading_arrays(44, "kd", "intensity", "n", "l"),
    ),
    GradingTest(
        "4.5 Blinn-Phong's highlight",
        STAGE4,
        2,
        VISIBLE,
        "blinn_phong",
        _shading_arrays(45, "ks", "intensity", "n", "l", "v", "p"),
    ),
    GradingTest(
        "4.6 mirror directions", STAGE4, 1, VISIBLE, "reflect", _shading_arrays(46, "d", "n")
    ),
    GradingTest(
        "4.7 the shadow test on a floor at 1e6 (shadow acne)",
        STAGE4,
        2,
        HIDDEN,
        "in_shadow",
        lambda: _shadow_test(47),
    ),
    GradingTest(
        "4.8 render scenes/classic_lit.json (320 x 240)",
        STAGE4,
        4,
        VISIBLE,
        "render",
        _scene_test(SCENES / "classic_lit.json", width=320, height=240),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "4.9 render scenes/shadow_on_billboard.json",
        STAGE4,
        3,
        VISIBLE,
        "render",
        _scene_test(SCENES / "shadow_on_billboard.json", width=240, height=180),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "4.10 render scenes/mirror_balls.json",
        STAGE4,
        3,
        HIDDEN,
        "render",
        _scene_test(SCENES / "mirror_balls.json", width=240, height=150),
        kind="image",
        mistakes=True,
    ),
    GradingTest(
        "4.11 render a hidden lit scene at 1e6, a ball touching the floor",
        STAGE4,
        3,
        HIDDEN,
        "render",
        _scene_test(HIDDEN_SCENES / "lit_far.json"),
        kind="image",
        mistakes=True,
    ),
]


def by_name(names: list[str] | None) -> list[GradingTest]:
    """The tests whose names start with any of ``names`` (all when None)."""
    if not names:
        return list(TESTS)
    return [t for t in TESTS if any(t.name.startswith(n) for n in names)]

"""The grading tests: per stage, with points and Gradescope visibility.

Each test names a task of :mod:`grading.child` and builds its inputs from a fixed seed or a
scene file. The expected result is that task run with the reference raykit; the submission's
result is the same task run in the child. Array tests compare every number within the stated
tolerance (a miss may be NaN or inf); image tests compare renders with :mod:`grading.compare`.

``visible`` tests show their result at once (and ship with the student release);
``after_due_date`` tests are hidden until then. A later stage (shading) adds its tests here.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "scenes"
HIDDEN_SCENES = Path(__file__).resolve().parent / "scenes"
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


STAGE1, STAGE2, STAGE3 = "1 line-scan camera", "2 rays, planes and spheres", "3 renderer"

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
]


def by_name(names: list[str] | None) -> list[GradingTest]:
    """The tests whose names start with any of ``names`` (all when None)."""
    if not names:
        return list(TESTS)
    return [t for t in TESTS if any(t.name.startswith(n) for n in names)]

"""The classic mistakes, made by the reference code made to make them: for renders, scans and
the array tests alike.

Each :class:`Mistake` swaps one piece of the reference code for the wrong version a student
typically writes (rows counted from the bottom, u and v swapped, fov_angle taken as horizontal,
a normal not made unit length, no offset for shadow rays, …) while a task runs in the grader.
When a submission's result fails a test, the grader runs that test's task with each mistake
made too; if one explains the result better than the reference does, the feedback names it
(and ``where``: the function a student makes it in). ``stage`` says which stage's code the
mistake is in; every mistake is tried on every graded picture (``in_renders``), since a camera
mistake spoils a lit picture too, and on every array test (``array_patches``: the same swap,
reaching also the names the array tasks call), skipped where it changes nothing. A stage-5
mistake is made in code only a distributed render runs (the sample patterns, the area lights,
the lens, glossy mirrors, the shutter), so it is tried on stage 5's pictures only
(:meth:`Mistake.tried_on`): elsewhere its picture is the right one, and rendering it would only
cost time.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from unittest import mock

import numpy as np

import raykit.billboards
import raykit.camera
import raykit.engine.noise
import raykit.engine.regions
import raykit.lights
import raykit.linescan.camera
import raykit.linescan.objects
import raykit.mirrors
import raykit.planes
import raykit.render
import raykit.sampling
import raykit.shading
import raykit.shadows
import raykit.spheres
import raykit.surfaces
from raykit.camera import Camera
from raykit.lights import PointLight, toward_light
from raykit.linescan.camera import LineCamera
from raykit.rays import MISS, dot, normalize
from raykit.sampling import point_on_disk
from raykit.spheres import sphere_roots


@dataclass(frozen=True)
class Mistake:
    """``says`` completes "your image matches what the renderer gives when …"."""

    key: str
    says: str
    patches: Callable[[], list] = field(default=lambda: [])
    after: Callable[[np.ndarray], np.ndarray] = field(default=lambda rgb: rgb)
    stage: str = "3"
    where: str = ""  # the student's function it is made in: "raykit/camera.py: _in_plane"
    arrays: Callable[[], list] | None = None  # patches for the array tests (None: ``patches``)
    in_renders: bool = True  # tried on rendered pictures too

    def tried_on(self, stage: str) -> bool:
        """Whether a picture of the test stage ``stage`` ("5 distributed ray tracing") can show
        this mistake: a stage-5 mistake only a distributed render's (the module page)."""
        return self.stage != "5" or stage.split()[0] == "5"

    @contextmanager
    def active(self, *, arrays: bool = False) -> Iterator[None]:
        """The mistake made while the block runs: for a picture, or (``arrays``) for the
        array tests' tasks."""
        patches = self.arrays if arrays and self.arrays is not None else self.patches
        with ExitStack() as stack:
            for patch in patches():
                stack.enter_context(patch)
            yield


def _frame(change: Callable[[np.ndarray, np.ndarray, np.ndarray], tuple]) -> list:
    """Patch every camera's u, v, w. A property on the class is a data descriptor, so it wins
    even over a frame a camera has already computed and cached."""

    def wrong(camera: Camera) -> tuple:
        return change(*ORIGINAL_CAMERA_FRAME(camera.eye, camera.lookat, camera.up))

    return [mock.patch.object(Camera, "frame", property(wrong))]


ORIGINAL_CAMERA_FRAME = raykit.camera.camera_frame


def _frame_function(change: Callable[[np.ndarray, np.ndarray, np.ndarray], tuple]) -> list:
    """Patch camera_frame itself (what test 3.1 calls) and every camera's frame."""

    def wrong(eye, lookat, up) -> tuple:
        return change(*ORIGINAL_CAMERA_FRAME(eye, lookat, up))

    return [mock.patch.object(raykit.camera, "camera_frame", wrong), *_frame(change)]


def _plane_size(size: Callable[[Camera], tuple[float, float]]) -> list:
    return [mock.patch.object(Camera, "plane_size", property(size))]


def _horizontal_fov(camera: Camera) -> tuple[float, float]:
    Wp = 2 * camera.d * math.tan(math.radians(camera.fov_angle) / 2)
    return Wp, Wp * camera.height / camera.width


def _no_aspect(camera: Camera) -> tuple[float, float]:
    Hp = 2 * camera.d * math.tan(math.radians(camera.fov_angle) / 2)
    return Hp, Hp


def _radians(camera: Camera) -> tuple[float, float]:
    Hp = 2 * camera.d * math.tan(camera.fov_angle / 2)
    return Hp * camera.width / camera.height, Hp


def _line_radians(camera: LineCamera) -> float:
    return 1.0 / math.tan(camera.fov_angle / 2.0)


def _rows_flipped_in_plane(camera: Camera, x, y) -> np.ndarray:
    """s·u + t·v with t counted from the bottom: t = -Hp/2 + y·Hp/height."""
    u, v, _ = camera.frame
    Wp, Hp = camera.plane_size
    s = -Wp / 2 + np.asarray(x, float) * (Wp / camera.width)
    t = -Hp / 2 + np.asarray(y, float) * (Hp / camera.height)
    return s[:, None] * u + t[:, None] * v


def _corner_pixel_x(pixels: int, samples: int = 1) -> np.ndarray:
    """x = -1 + (i + k/n)·2/N: each pixel's (or sample's) left edge, not its centre."""
    i = np.repeat(np.arange(pixels), samples)
    k = np.tile(np.arange(samples), pixels)
    return -1.0 + (i + k / samples) * (2.0 / pixels)


def _corner_in_plane(camera: Camera, x, y) -> np.ndarray:
    """s·u + t·v half a pixel up and left: the pixel's corner, x - 0.5, not its centre x."""
    u, v, _ = camera.frame
    Wp, Hp = camera.plane_size
    s = -Wp / 2 + (np.asarray(x, float) - 0.5) * (Wp / camera.width)
    t = Hp / 2 - (np.asarray(y, float) - 0.5) * (Hp / camera.height)
    return s[:, None] * u + t[:, None] * v


def _stretched(camera: Camera, x, y) -> np.ndarray:
    """The image plane's points with the slide's u_i = i·2/N_cols: the first and the last
    pixel centres on the plane's edges, the rest spread evenly between."""
    u, v, _ = camera.frame
    Wp, Hp = camera.plane_size
    s = -Wp / 2 + (np.asarray(x, float) - 0.5) * (Wp / max(camera.width - 1, 1))
    t = Hp / 2 - (np.asarray(y, float) - 0.5) * (Hp / max(camera.height - 1, 1))
    return s[:, None] * u + t[:, None] * v


def _far_root(origins, directions, center, radius):
    t0, t1, discriminant = sphere_roots(origins, directions, center, radius)
    far = np.fmax(t0, t1)
    with np.errstate(invalid="ignore"):
        return np.where((discriminant >= 0) & (far > 0), far, MISS)


def _any_root(origins, directions, center, radius):
    t0, t1, discriminant = sphere_roots(origins, directions, center, radius)
    return np.where(discriminant >= 0, np.fmin(t0, t1), MISS)


def _plane_t_zero(origins, directions, a, n):
    """t >= 0 where the rule is t > 0: a ray starting on the plane hits it at t = 0."""
    d_dot_n, a_minus_o_dot_n = dot(directions, n), dot(a - origins, n)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = a_minus_o_dot_n / d_dot_n
    return np.where((d_dot_n != 0) & (t >= 0), t, MISS)


def _plane_any_side(origins, directions, a, n):
    with np.errstate(divide="ignore", invalid="ignore"):
        t = dot(a - origins, n) / dot(directions, n)
    return np.where(np.isfinite(t), t, MISS)


def _rows_flipped_texels(alpha, beta, width, height):
    row, column = ORIGINAL_TEXEL_INDICES(alpha, beta, width, height)
    return height - 1 - row, column


ORIGINAL_TEXEL_INDICES = raykit.billboards.texel_indices


def _normal_not_unit(points, center, radius):
    return points - center


def _light_reversed(light, points):
    l, distance = toward_light(light, points)
    return -l, distance


def _no_offset(cast, surface, l, distance):
    return cast(surface.points, l, distance).t < distance


def _reflect_sign(d, n):
    return d + 2.0 * dot(d, n)[:, None] * n


def _half_vector_not_unit(ks, intensity, n, l, v, p):
    return ks * intensity * (np.maximum(0.0, dot(n, l + v)) ** p)[:, None]


def _one_point_light(light, uniforms):
    """The area light as one point light at its centre, whatever the uniform numbers: hard
    shadows."""
    centre = light.corner + 0.5 * light.edge1 + 0.5 * light.edge2
    return PointLight(np.broadcast_to(centre, (len(uniforms), 3)), light.color)


def _lens_radius_aperture(eye, u, v, aperture, uniforms):
    """The lens of radius aperture: twice the lens, twice the blur."""
    disk = point_on_disk(uniforms)
    return np.asarray(eye, float) + aperture * (
        disk[:, 0:1] * np.asarray(u, float) + disk[:, 1:2] * np.asarray(v, float)
    )


def _not_stratified(cells, n, uniforms):
    """The uniform numbers as they are: a random set, not one sample in each cell."""
    return np.array(uniforms, dtype=float)


def _cell_centres(cells, n, uniforms):
    """The cells' centres ((i + ½)/n, (j + ½)/n): a regular grid, the numbers unused."""
    cells = np.asarray(cells)
    return (np.column_stack([cells % n, cells // n]).astype(float) + 0.5) / n


def _jittered(wrong: Callable) -> Callable[[], list]:
    """Patch jittered_point where the array tasks find it and where the renderer's noise
    calls it."""
    return _patch(
        (raykit.sampling, "jittered_point", wrong), (raykit.engine.noise, "jittered_point", wrong)
    )


def _basis_not_unit(r):
    """u = t × w not divided by its length: u is not unit length, so the square of side a
    the perturbation moves in is stretched along u."""
    w = normalize(r)
    t = w.copy()
    t[np.arange(len(w)), np.argmin(np.abs(w), axis=1)] = 1.0
    u = np.cross(t, w)
    return u, np.cross(w, u), w


def _time_per_pixel(shutter_open, shutter_close, uniforms):
    """One time per pixel, its first sample's, shared by all its samples (rays)."""
    uniforms = np.asarray(uniforms, dtype=float)
    first = shutter_open + uniforms[:, :1] * (shutter_close - shutter_open)
    return np.repeat(first, uniforms.shape[1], axis=1)


def _shading(name: str, wrong: Callable, *modules) -> Callable[[], list]:
    """Patch ``name`` in raykit.shading (what the renderer calls) and in ``modules`` (where the
    array tests' tasks import it from)."""
    modules = modules or (raykit.shading,)
    return lambda: [mock.patch.object(module, name, wrong) for module in modules]


def _patch(*where: tuple) -> Callable[[], list]:
    """(module or class, name, wrong) triples, patched together."""
    return lambda: [mock.patch.object(owner, name, wrong) for owner, name, wrong in where]


# ``where`` always names a function the student writes (the release's stubs): a mistake made
# in given code a student function calls (Camera.plane_size, which _in_plane reads) is named
# by that student function, where a student computing it wrongly would have written it
CAMERA = "raykit/camera.py: _in_plane"
SWAP_UV = lambda u, v, w: (v, u, w)  # noqa: E731

MISTAKES = [
    Mistake(
        "rows_flipped",
        "image rows are counted from the bottom (the picture is upside down)",
        after=lambda rgb: rgb[::-1],
        where=CAMERA,
        arrays=_patch((raykit.camera, "_in_plane", _rows_flipped_in_plane)),
    ),
    Mistake(
        "u_v_swapped",
        "u and v are swapped",
        patches=lambda: _frame(SWAP_UV),
        where="raykit/camera.py: camera_frame",
        arrays=lambda: _frame_function(SWAP_UV),
    ),
    Mistake(
        "u_negated",
        "u points left instead of right (the picture is mirrored)",
        patches=lambda: _frame(lambda u, v, w: (-u, v, w)),
        where=CAMERA,
    ),
    Mistake(
        "fov_horizontal",
        "fov_angle is used as the horizontal field of view",
        patches=lambda: _plane_size(_horizontal_fov),
        where=CAMERA,
    ),
    Mistake(
        "aspect_ignored",
        "the aspect ratio is ignored (the image plane is made square)",
        patches=lambda: _plane_size(_no_aspect),
        where=CAMERA,
    ),
    Mistake(
        "pixel_corners",
        "rays go through pixel corners instead of pixel centres (as the slide's second formula "
        "u_i = i·2/N_cols does when its first N_cols positions are kept)",
        patches=_patch((raykit.camera, "_in_plane", _corner_in_plane)),
        where=CAMERA,
    ),
    Mistake(
        "pixel_x_corners",
        "pixel positions are the pixels' left edges x = -1 + i·2/N instead of their centres "
        "x_i = -1 + (i + 0.5)·2/N (every position half a pixel off)",
        patches=_patch((raykit.linescan.camera, "pixel_x", _corner_pixel_x)),
        stage="1",
        where="raykit/linescan/camera.py: pixel_x",
    ),
    Mistake(
        "slide_second_formula",
        "pixels are placed by the slide's second formula u_i = i·2/N_cols, i = 0, ±1, ±2, …, "
        "±N_cols/2 (N_cols + 1 positions spread over N_cols pixels: the picture is stretched)",
        patches=_patch((raykit.camera, "_in_plane", _stretched)),
        where=CAMERA,
    ),
    Mistake(
        "degrees_as_radians",
        "fov_angle in degrees is given to tan() as radians",
        patches=lambda: [
            *_plane_size(_radians),
            mock.patch.object(LineCamera, "D", property(_line_radians)),
        ],
        where=CAMERA,
    ),
    Mistake(
        "far_root",
        "the far root of the quadratic is taken instead of the near one",
        patches=_patch(
            (raykit.render, "hit_sphere", _far_root),
            (raykit.spheres, "hit_sphere", _far_root),
            (raykit.linescan.objects, "hit_sphere", _far_root),
        ),
        where="raykit/spheres.py: hit_sphere",
    ),
    Mistake(
        "textbook_discriminant",
        "the discriminant is the textbook's D = B² - 4AC, whose digits are lost for a small "
        "sphere far away (b'² and AC huge and nearly equal): use the stable form "
        "Δ = A·(R² - |f - (b'/A)·d|²)",
        patches=_patch((raykit.spheres, "hit_sphere", raykit.spheres.hit_sphere_textbook)),
        where="raykit/spheres.py: sphere_roots",
        in_renders=False,
    ),
    Mistake(
        "texture_rows_flipped",
        "texture rows are read upside down",
        patches=_patch((raykit.billboards, "texel_indices", _rows_flipped_texels)),
        where="raykit/billboards.py: texel_indices",
    ),
    Mistake(
        "behind_the_eye",
        "hits behind the eye (t < 0) are accepted",
        patches=_patch(
            (raykit.render, "hit_sphere", _any_root),
            (raykit.spheres, "hit_sphere", _any_root),
            (raykit.billboards, "hit_plane", _plane_any_side),
            (raykit.planes, "hit_plane", _plane_any_side),
        ),
        where="raykit/spheres.py: hit_sphere, raykit/planes.py: hit_plane",
    ),
    Mistake(
        "t_zero_accepted",
        "a hit at t = 0 (where the ray starts) is accepted: the rule is t > 0, not t >= 0",
        patches=_patch((raykit.planes, "hit_plane", _plane_t_zero)),
        where="raykit/planes.py: hit_plane",
        in_renders=False,
    ),
    Mistake(
        "normal_not_unit",
        "the sphere normal p - c is not divided by r (not unit length)",
        patches=_shading("sphere_normals", _normal_not_unit, raykit.surfaces, raykit.spheres),
        stage="4",
        where="raykit/spheres.py: sphere_normals",
    ),
    Mistake(
        "light_reversed",
        "l points from the light to the surface instead of toward the light",
        patches=_shading("toward_light", _light_reversed, raykit.shading, raykit.lights),
        stage="4",
        where="raykit/lights.py: toward_light",
    ),
    Mistake(
        "no_offset",
        "shadow rays start exactly on the surface (shadow acne: no offset)",
        patches=_shading("in_shadow", _no_offset, raykit.shading, raykit.shadows),
        stage="4",
        where="raykit/shadows.py: in_shadow",
    ),
    Mistake(
        "reflect_sign",
        "the mirror direction is d + 2(d·n)n instead of d - 2(d·n)n",
        patches=_shading("reflect", _reflect_sign, raykit.shading, raykit.mirrors),
        stage="4",
        where="raykit/mirrors.py: reflect",
    ),
    Mistake(
        "half_vector_not_unit",
        "the half vector h = l + v is not normalised",
        patches=_shading("blinn_phong", _half_vector_not_unit),
        stage="4",
        where="raykit/shading.py: blinn_phong",
    ),
    Mistake(
        "area_light_as_point",
        "the area light is one point light at its centre instead of a point of it sampled per "
        "shadow ray (hard shadows, no penumbra)",
        patches=_patch(
            (raykit.lights, "sampled", _one_point_light),
            (raykit.shading, "sampled", _one_point_light),
        ),
        stage="5",
        where="raykit/lights.py: sampled",
    ),
    Mistake(
        "aperture_as_radius",
        "the aperture is taken as the lens's radius instead of its diameter (a lens twice as "
        "wide: twice the blur)",
        patches=_patch(
            (raykit.sampling, "point_on_lens", _lens_radius_aperture),
            (raykit.camera, "point_on_lens", _lens_radius_aperture),
        ),
        stage="5",
        where="raykit/sampling.py: point_on_lens",
    ),
    Mistake(
        "not_jittered",
        "the samples are not jittered: each is anywhere in the square (the uniform numbers as "
        "they are), not one in each of the n x n cells",
        patches=_jittered(_not_stratified),
        stage="5",
        where="raykit/sampling.py: jittered_point",
    ),
    Mistake(
        "jitter_missing",
        "the samples sit at the centres of their cells (a regular grid): the uniform numbers "
        "do not jitter them within the cells",
        patches=_jittered(_cell_centres),
        stage="5",
        where="raykit/sampling.py: jittered_point",
    ),
    Mistake(
        "basis_not_orthonormal",
        "the basis around r is not orthonormal: u = t × w is not divided by its length, so "
        "the glossy perturbation is stretched along u",
        patches=_patch((raykit.sampling, "basis_around", _basis_not_unit)),
        stage="5",
        where="raykit/sampling.py: basis_around",
    ),
    Mistake(
        "time_per_pixel",
        "each pixel has one time in the shutter interval, shared by its samples, instead of a "
        "time per ray (the moving object is not blurred but noisy: each pixel sees it at one "
        "instant)",
        patches=_patch(
            (raykit.sampling, "shutter_times", _time_per_pixel),
            (raykit.engine.regions, "shutter_times", _time_per_pixel),
        ),
        stage="5",
        where="raykit/sampling.py: shutter_times",
    ),
]

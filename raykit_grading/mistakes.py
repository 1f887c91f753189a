"""The classic mistakes of the 3D renderer and of shading, rendered by the reference code made
to make them.

Each :class:`Mistake` swaps one piece of the reference renderer for the wrong version a student
typically writes (rows counted from the bottom, u and v swapped, fov_angle taken as horizontal,
a normal not made unit length, no offset for shadow rays, …) while the task runs in the grader.
When a submission's image fails, the grader compares it with these too; if one matches it
better than the reference does, the feedback says which. ``stage`` says which stage's code the
mistake is in; every mistake is tried on every graded render, since a camera mistake spoils a
lit picture too.
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
import raykit.engine.regions
import raykit.render
import raykit.shading
import raykit.surfaces
from raykit.camera import Camera
from raykit.lights import toward_light
from raykit.rays import MISS, dot
from raykit.spheres import sphere_roots


@dataclass(frozen=True)
class Mistake:
    """``says`` completes "your image matches what the renderer gives when …"."""

    key: str
    says: str
    patches: Callable[[], list] = field(default=lambda: [])
    after: Callable[[np.ndarray], np.ndarray] = field(default=lambda rgb: rgb)
    stage: str = "3"

    @contextmanager
    def active(self) -> Iterator[None]:
        with ExitStack() as stack:
            for patch in self.patches():
                stack.enter_context(patch)
            yield


def _frame(change: Callable[[np.ndarray, np.ndarray, np.ndarray], tuple]) -> list:
    """Patch every camera's u, v, w. A property on the class is a data descriptor, so it wins
    even over a frame a camera has already computed and cached."""

    def wrong(camera: Camera) -> tuple:
        return change(*raykit.camera.camera_frame(camera.eye, camera.lookat, camera.up))

    return [mock.patch.object(Camera, "frame", property(wrong))]


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


def _shading(name: str, wrong: Callable, module=raykit.shading) -> Callable[[], list]:
    return lambda: [mock.patch.object(module, name, wrong)]


MISTAKES = [
    Mistake(
        "rows_flipped",
        "image rows are counted from the bottom (the picture is upside down)",
        after=lambda rgb: rgb[::-1],
    ),
    Mistake(
        "u_v_swapped", "u and v are swapped", patches=lambda: _frame(lambda u, v, w: (v, u, w))
    ),
    Mistake(
        "u_negated",
        "u points left instead of right (the picture is mirrored)",
        patches=lambda: _frame(lambda u, v, w: (-u, v, w)),
    ),
    Mistake(
        "fov_horizontal",
        "fov_angle is used as the horizontal field of view",
        patches=lambda: _plane_size(_horizontal_fov),
    ),
    Mistake(
        "aspect_ignored",
        "the aspect ratio is ignored (the image plane is made square)",
        patches=lambda: _plane_size(_no_aspect),
    ),
    Mistake(
        "pixel_corners",
        "rays go through pixel corners instead of pixel centres (as the slide's second formula "
        "u_i = i·2/N_cols does when its first N_cols positions are kept)",
        patches=lambda: [
            mock.patch.object(raykit.engine.regions, "sample_offsets", lambda n: np.zeros((1, 2)))
        ],
    ),
    Mistake(
        "slide_second_formula",
        "pixels are placed by the slide's second formula u_i = i·2/N_cols, i = 0, ±1, …, "
        "±N_cols/2 (N_cols + 1 positions spread over N_cols pixels: the picture is stretched)",
        patches=lambda: [mock.patch.object(raykit.camera, "_in_plane", _stretched)],
    ),
    Mistake(
        "degrees_as_radians",
        "fov_angle in degrees is given to tan() as radians",
        patches=lambda: _plane_size(_radians),
    ),
    Mistake(
        "far_root",
        "the far root of the quadratic is taken instead of the near one",
        patches=lambda: [mock.patch.object(raykit.render, "hit_sphere", _far_root)],
    ),
    Mistake(
        "texture_rows_flipped",
        "texture rows are read upside down",
        patches=lambda: [
            mock.patch.object(raykit.billboards, "texel_indices", _rows_flipped_texels)
        ],
    ),
    Mistake(
        "behind_the_eye",
        "hits behind the eye (t < 0) are accepted",
        patches=lambda: [
            mock.patch.object(raykit.render, "hit_sphere", _any_root),
            mock.patch.object(raykit.billboards, "hit_plane", _plane_any_side),
        ],
    ),
    Mistake(
        "normal_not_unit",
        "the sphere normal p - c is not divided by r (not unit length)",
        patches=_shading("sphere_normals", _normal_not_unit, raykit.surfaces),
        stage="4",
    ),
    Mistake(
        "light_reversed",
        "l points from the light to the surface instead of toward the light",
        patches=_shading("toward_light", _light_reversed),
        stage="4",
    ),
    Mistake(
        "no_offset",
        "shadow rays start exactly on the surface (shadow acne: no offset)",
        patches=_shading("in_shadow", _no_offset),
        stage="4",
    ),
    Mistake(
        "reflect_sign",
        "the mirror direction is d + 2(d·n)n instead of d - 2(d·n)n",
        patches=_shading("reflect", _reflect_sign),
        stage="4",
    ),
    Mistake(
        "half_vector_not_unit",
        "the half vector h = l + v is not normalised",
        patches=_shading("blinn_phong", _half_vector_not_unit),
        stage="4",
    ),
]

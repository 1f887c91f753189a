"""Repeats :mod:`raykit.camera` for one image point: its viewing ray, from the camera's
numbers as plain floats, through the pinhole or (stage 5) from a point of the thin lens."""

from __future__ import annotations

import math
from typing import NamedTuple

from numba import njit

from raykit.engine.compiled.compiling import INLINED, ONE_RAY
from raykit.engine.compiled.rays import Ray
from raykit.engine.compiled.sampling import point_on_lens
from raykit.scene import Scene


class CameraNumbers(NamedTuple):
    """The camera (:mod:`raykit.camera`) as :func:`rays_through` uses it, plain floats that the
    kernels keep in registers: the eye e (``e0``, ``e1``, ``e2``), the frame u, v, w, the image
    plane's ``left`` edge -Wp/2 and step ``across`` Wp/width, its ``top`` edge Hp/2 and step
    ``down`` Hp/height, the distance ``d`` to it, and ``ortho``, 1.0 for an orthographic
    camera, else 0.0 (:func:`camera_tuple`)."""

    e0: float
    e1: float
    e2: float
    u0: float
    u1: float
    u2: float
    v0: float
    v1: float
    v2: float
    w0: float
    w1: float
    w2: float
    left: float
    across: float
    top: float
    down: float
    d: float
    ortho: float


@njit(**ONE_RAY)
def rays_through(camera, x, y):
    """Repeats :func:`raykit.camera.rays_through` for one image point (x, y): its
    :class:`~raykit.engine.compiled.rays.Ray`. ``camera``: :class:`CameraNumbers`."""
    s = camera.left + x * camera.across
    t = camera.top - y * camera.down
    p0 = s * camera.u0 + t * camera.v0
    p1 = s * camera.u1 + t * camera.v1
    p2 = s * camera.u2 + t * camera.v2
    if camera.ortho != 0:  # orthographic: origin e + s·u + t·v, direction -w
        return Ray(o0=camera.e0 + p0, o1=camera.e1 + p1, o2=camera.e2 + p2,
                   d0=-camera.w0, d1=-camera.w1, d2=-camera.w2)  # fmt: skip
    x0 = p0 - camera.d * camera.w0
    x1 = p1 - camera.d * camera.w1
    x2 = p2 - camera.d * camera.w2
    length = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    return Ray(o0=camera.e0, o1=camera.e1, o2=camera.e2,
               d0=x0 / length, d1=x1 / length, d2=x2 / length)  # fmt: skip


# INLINED, and the lens's kernels it calls (point_on_lens, point_on_disk, cos_sin): a loop of it
# over a batch's samples (sampled_lanes) becomes vector instructions only when each is copied
# into it; left to LLVM's rule, they stayed calls, one ray at a time
@njit(**INLINED)
def thin_lens_rays(camera, lens, x, y, xi1, xi2):
    """Repeats :func:`raykit.camera.thin_lens_rays` for one image point (x, y) and the uniform
    numbers (ξ1, ξ2) of its point on the lens: its :class:`~raykit.engine.compiled.rays.Ray`,
    from r on the lens toward s on the focal plane, formed relative to the eye. ``lens`` is the
    aperture and f/d (:func:`lens_tuple`)."""
    c = camera
    aperture, f_over_d = lens
    s = c.left + x * c.across
    t = c.top - y * c.down
    pinhole0 = s * c.u0 + t * c.v0 - c.d * c.w0  # P - e, the pinhole ray's direction
    pinhole1 = s * c.u1 + t * c.v1 - c.d * c.w1
    pinhole2 = s * c.u2 + t * c.v2 - c.d * c.w2
    r0, r1, r2 = point_on_lens(
        0.0, 0.0, 0.0, c.u0, c.u1, c.u2, c.v0, c.v1, c.v2, aperture, xi1, xi2
    )
    x0 = f_over_d * pinhole0 - r0
    x1 = f_over_d * pinhole1 - r1
    x2 = f_over_d * pinhole2 - r2
    length = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    return Ray(o0=c.e0 + r0, o1=c.e1 + r1, o2=c.e2 + r2, d0=x0 / length, d1=x1 / length,
               d2=x2 / length)  # fmt: skip


def lens_tuple(scene: Scene) -> tuple:
    """The thin lens's numbers as :func:`thin_lens_rays` takes them: the aperture and f/d,
    computed as :func:`raykit.camera.thin_lens_rays` computes them (aperture 0: no lens)."""
    camera = scene.camera
    return float(camera.aperture), float(camera.focus / camera.d)


def camera_tuple(scene: Scene) -> CameraNumbers:
    """The camera's :class:`CameraNumbers`, computed as :func:`raykit.camera.rays_through`
    computes them (numbers, not arrays, so that a loop of :func:`rays_through` keeps them in
    registers)."""
    camera = scene.camera
    u, v, w = camera.frame
    Wp, Hp = camera.plane_size
    plane = (-Wp / 2, Wp / camera.width, Hp / 2, Hp / camera.height, camera.d,
             float(camera.projection == "orthographic"))  # fmt: skip
    return CameraNumbers(*(float(x) for x in (*camera.eye, *u, *v, *w, *plane)))

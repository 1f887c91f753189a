"""Repeats :mod:`raykit.camera` for one image point: its viewing ray, from the camera's
numbers as plain floats, through the pinhole or (stage 5) from a point of the thin lens."""

from __future__ import annotations

import math

from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY
from raykit.engine.compiled.rays import Ray
from raykit.engine.compiled.sampling import point_on_lens
from raykit.scene import Scene


@njit(**ONE_RAY)
def rays_through(camera, x, y):
    """Repeats :func:`raykit.camera.rays_through` for one image point (x, y): its
    :class:`~raykit.engine.compiled.rays.Ray`. ``camera`` is the eye e, u, v, w, then -Wp/2,
    Wp/width, Hp/2, Hp/height, d and whether it is orthographic (1.0) or not (0.0), as 18
    numbers: :func:`camera_tuple`."""
    e0, e1, e2, u0, u1, u2, v0, v1, v2, w0, w1, w2, left, across, top, down, d, ortho = camera
    s = left + x * across
    t = top - y * down
    p0 = s * u0 + t * v0
    p1 = s * u1 + t * v1
    p2 = s * u2 + t * v2
    if ortho != 0:  # orthographic: origin e + s·u + t·v, direction -w
        return Ray(o0=e0 + p0, o1=e1 + p1, o2=e2 + p2, d0=-w0, d1=-w1, d2=-w2)
    x0 = p0 - d * w0
    x1 = p1 - d * w1
    x2 = p2 - d * w2
    length = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    return Ray(o0=e0, o1=e1, o2=e2, d0=x0 / length, d1=x1 / length, d2=x2 / length)


@njit(**ONE_RAY)
def thin_lens_rays(camera, lens, x, y, xi1, xi2):
    """Repeats :func:`raykit.camera.thin_lens_rays` for one image point (x, y) and the uniform
    numbers (ξ1, ξ2) of its point on the lens: its :class:`~raykit.engine.compiled.rays.Ray`,
    from r on the lens toward s on the focal plane, formed relative to the eye. ``lens`` is the
    aperture and f/d (:func:`lens_tuple`)."""
    e0, e1, e2, u0, u1, u2, v0, v1, v2, w0, w1, w2, left, across, top, down, d, _ = camera
    aperture, f_over_d = lens
    s = left + x * across
    t = top - y * down
    pinhole0 = s * u0 + t * v0 - d * w0  # P - e, the pinhole ray's direction
    pinhole1 = s * u1 + t * v1 - d * w1
    pinhole2 = s * u2 + t * v2 - d * w2
    r0, r1, r2 = point_on_lens(0.0, 0.0, 0.0, u0, u1, u2, v0, v1, v2, aperture, xi1, xi2)
    x0 = f_over_d * pinhole0 - r0
    x1 = f_over_d * pinhole1 - r1
    x2 = f_over_d * pinhole2 - r2
    length = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    return Ray(o0=e0 + r0, o1=e1 + r1, o2=e2 + r2, d0=x0 / length, d1=x1 / length,
               d2=x2 / length)  # fmt: skip


def lens_tuple(scene: Scene) -> tuple:
    """The thin lens's numbers as :func:`thin_lens_rays` takes them: the aperture and f/d,
    computed as :func:`raykit.camera.thin_lens_rays` computes them (aperture 0: no lens)."""
    camera = scene.camera
    return float(camera.aperture), float(camera.focus / camera.d)


def camera_tuple(scene: Scene) -> tuple:
    """The camera's numbers as :func:`rays_through` computes them, as plain floats (a tuple of
    numbers, not arrays, so that a loop of :func:`rays_through` keeps them in registers)."""
    camera = scene.camera
    u, v, w = camera.frame
    Wp, Hp = camera.plane_size
    plane = (-Wp / 2, Wp / camera.width, Hp / 2, Hp / camera.height, camera.d,
             float(camera.projection == "orthographic"))  # fmt: skip
    return tuple(float(x) for x in (*camera.eye, *u, *v, *w, *plane))

"""Repeats :mod:`raykit.camera` for one image point: its viewing ray, from the camera's
numbers as plain floats."""

from __future__ import annotations

import math
from typing import NamedTuple

from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY
from raykit.engine.compiled.rays import Ray
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

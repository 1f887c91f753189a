"""Repeats :mod:`raykit.surfaces` for one hit: its point, normal and rounding bound, and
where a ray leaving it starts."""

from __future__ import annotations

import numpy as np
from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY
from raykit.surfaces import OFFSET_FACTOR

EPS = float(np.finfo(np.float64).eps)  # the rounding unit of raykit.surfaces' error bound


@njit(**ONE_RAY)
def surface_points(arrays, shading, o0, o1, o2, d0, d1, d2, hit, t):
    """Repeats :func:`raykit.surfaces.surface_points` for one ray and its hit (object ``hit`` at
    ``t``): ``(p0, p1, p2, n0, n1, n2, error)``, the point p = o + t·d, the unit normal n on the
    side the ray arrives at, and the point's rounding bound."""
    p0, p1, p2 = o0 + t * d0, o1 + t * d1, o2 + t * d2
    spheres = len(arrays.radii)
    if hit < spheres:  # raykit.spheres.sphere_normals
        R = arrays.radii[hit]
        centers = arrays.centers
        n0 = (p0 - centers[hit, 0]) / R
        n1 = (p1 - centers[hit, 1]) / R
        n2 = (p2 - centers[hit, 2]) / R
    else:  # raykit.billboards.billboard_normals: the side the ray arrives at
        normals, board = shading.board_normals, hit - spheres
        m0, m1, m2 = normals[board, 0], normals[board, 1], normals[board, 2]
        facing = -1.0 if d0 * m0 + d1 * m1 + d2 * m2 > 0 else 1.0
        n0, n1, n2 = facing * m0, facing * m1, facing * m2
    error = EPS * (max(abs(o0), abs(o1), abs(o2)) + t)
    return p0, p1, p2, n0, n1, n2, error


@njit(**ONE_RAY)
def start(p0, p1, p2, n0, n1, n2, error, d0, d1, d2):
    """Repeats :meth:`raykit.surfaces.SurfacePoints.start` for a ray leaving p along d: p moved
    ε = OFFSET_FACTOR x ``error`` along n, to the side d leaves towards."""
    side = 1.0 if n0 * d0 + n1 * d1 + n2 * d2 >= 0 else -1.0
    epsilon = OFFSET_FACTOR * error
    offset = side * epsilon
    return p0 + offset * n0, p1 + offset * n1, p2 + offset * n2

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
    side the ray arrives at, and the point's rounding bound: :func:`point_and_normal` of what
    the point reads of its object (:func:`hit_object`)."""
    a0, a1, a2, R = hit_object(arrays, shading, hit)
    return point_and_normal(o0, o1, o2, d0, d1, d2, t, a0, a1, a2, R)


@njit(**ONE_RAY)
def hit_object(arrays, shading, hit):
    """What the surface point of a hit on object ``hit`` reads of the object, for
    :func:`point_and_normal`: ``(a0, a1, a2, R)``, a sphere's centre and radius, or a
    billboard's unit normal and 0."""
    spheres = len(arrays.radii)
    if hit < spheres:
        centers = arrays.centers
        return centers[hit, 0], centers[hit, 1], centers[hit, 2], arrays.radii[hit]
    normals, board = shading.board_normals, hit - spheres
    return normals[board, 0], normals[board, 1], normals[board, 2], 0.0


@njit(**ONE_RAY)
def point_and_normal(o0, o1, o2, d0, d1, d2, t, a0, a1, a2, R):
    """:func:`surface_points` of a ray's hit, from what it reads of its object
    (:func:`hit_object`): a sphere's (R > 0) normal is (p - a)/R, a billboard's (R = 0) its
    normal a, turned to the side the ray arrives at. Both are made and one is kept, with no
    branch, so that a loop of it over many rays is one the compiler turns into vector
    instructions (:func:`~.shading.surface_lanes`); the other, made of numbers not meant for it,
    is thrown away."""
    p0, p1, p2 = o0 + t * d0, o1 + t * d1, o2 + t * d2
    s0, s1, s2 = (p0 - a0) / R, (p1 - a1) / R, (p2 - a2) / R  # raykit.spheres.sphere_normals
    # raykit.billboards.billboard_normals: the side the ray arrives at
    facing = -1.0 if d0 * a0 + d1 * a1 + d2 * a2 > 0 else 1.0
    sphere = R > 0
    n0 = s0 if sphere else facing * a0
    n1 = s1 if sphere else facing * a1
    n2 = s2 if sphere else facing * a2
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

"""Repeats :mod:`raykit.spheres` for one ray: where it meets a sphere."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY
from raykit.engine.compiled.rays import nearest_positive


@njit(**ONE_RAY)
def hit_sphere(o0, o1, o2, d0, d1, d2, c0, c1, c2, R) -> float:
    """Repeats :func:`raykit.spheres.hit_sphere` (through :func:`raykit.spheres.sphere_roots`,
    the stable form; its docstring derives it from the slide's A, B, C and D) for one ray."""
    f0 = o0 - c0
    f1 = o1 - c1
    f2 = o2 - c2
    A = d0 * d0 + d1 * d1 + d2 * d2
    b = f0 * d0 + f1 * d1 + f2 * d2  # b' = B/2
    C = (f0 * f0 + f1 * f1 + f2 * f2) - R * R
    k = b / A
    x0 = f0 - k * d0  # centre -> closest point on the line
    x1 = f1 - k * d1
    x2 = f2 - k * d2
    discriminant = A * (R * R - (x0 * x0 + x1 * x1 + x2 * x2))  # Δ = D/4
    if not discriminant >= 0:
        return np.inf
    q = -(b + math.copysign(math.sqrt(discriminant), b))
    return nearest_positive(q / A, C / q)


@njit(**ONE_RAY)
def center_at(c0, c1, c2, v0, v1, v2, T):
    """Repeats :func:`raykit.spheres.center_at` for one ray: the centre c + T·v of a sphere
    moving with velocity v, at the ray's time T."""
    return c0 + T * v0, c1 + T * v1, c2 + T * v2

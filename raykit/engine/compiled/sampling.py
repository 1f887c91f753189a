"""Repeats :mod:`raykit.sampling` for one sample: the patterns of distributed ray tracing from
its uniform numbers (ξ1, ξ2), the same float64 operations in the same order, so the same bits.
The cosine and sine of the lens's concentric map are :func:`raykit.sampling._cos_sin`'s series,
never the C library's, which differs from numpy's from one processor to the next."""

from __future__ import annotations

import math

from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY


@njit(**ONE_RAY)
def point_in_pixel(row, col, u1, u2):
    """Repeats :func:`raykit.sampling.point_in_pixel` for one sample: (x, y) = (c + ξ1, r + ξ2)
    in pixel (row, col)."""
    return float(col) + u1, float(row) + u2


@njit(**ONE_RAY)
def jittered_point(cell, n, u1, u2):
    """Repeats :func:`raykit.sampling.jittered_point` for one cell of the n x n grid: ((i +
    ξ1)/n, (j + ξ2)/n) for cell = i + n·j."""
    return (float(cell % n) + u1) / n, (float(cell // n) + u2) / n


@njit(**ONE_RAY)
def point_on_parallelogram(c0, c1, c2, a0, a1, a2, b0, b1, b2, u1, u2):
    """Repeats :func:`raykit.sampling.point_on_parallelogram` for one sample: c + ξ1·a + ξ2·b."""
    return c0 + u1 * a0 + u2 * b0, c1 + u1 * a1 + u2 * b1, c2 + u1 * a2 + u2 * b2


@njit(**ONE_RAY)
def cos_sin(angle):
    """Repeats :func:`raykit.sampling._cos_sin` for one angle in [-π/4, π/4]: its Taylor
    series, Horner's way, in the reference's order."""
    x2 = angle * angle
    cos = 1.0
    sin = 1.0
    for k in range(11, 0, -1):
        cos = 1.0 - x2 / ((2 * k - 1) * (2 * k)) * cos
        sin = 1.0 - x2 / ((2 * k) * (2 * k + 1)) * sin
    return cos, angle * sin


@njit(**ONE_RAY)
def point_on_disk(u1, u2):
    """Repeats :func:`raykit.sampling.point_on_disk` for one sample: Shirley and Chiu's
    concentric map of (ξ1, ξ2) to the unit disk."""
    a = 2.0 * u1 - 1.0
    b = 2.0 * u2 - 1.0
    wide = abs(a) > abs(b)
    radius = a if wide else b
    if radius == 0:  # the centre: any angle (the reference's 0/0 is replaced so)
        angle = 0.0
    else:
        angle = (math.pi / 4) * (b / a if wide else a / b)
    cos, sin = cos_sin(angle)
    if wide:
        return radius * cos, radius * sin
    return radius * sin, radius * cos


@njit(**ONE_RAY)
def point_on_lens(e0, e1, e2, u0, u1, u2, v0, v1, v2, aperture, x1, x2):
    """Repeats :func:`raykit.sampling.point_on_lens` for one sample (ξ1, ξ2) = (``x1``, ``x2``):
    e + (aperture/2)·(x·u + y·v), (x, y) the point on the unit disk."""
    x, y = point_on_disk(x1, x2)
    radius = aperture / 2.0
    return (
        e0 + radius * (x * u0 + y * v0),
        e1 + radius * (x * u1 + y * v1),
        e2 + radius * (x * u2 + y * v2),
    )

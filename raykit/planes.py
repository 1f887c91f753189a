"""Ray–plane intersection: the plane through point a with normal n.

A point p lies on the plane when (p - a)·n = 0. Putting in the ray p(t) = o + t·d gives

    t = ((a - o)·n) / (d·n)

(see :mod:`raykit.rays` for the shapes and the miss convention). The difference a - o is taken
first, so a scene far from the origin loses no more digits than its own size forces.

The same lines serve the line-scan world, where a "plane" is a line with a 2D normal, and the
billboards (:mod:`raykit.billboards`), which are bounded pieces of a plane.
"""

from __future__ import annotations

import numpy as np

from raykit.rays import MISS


def hit_plane(
    origins: np.ndarray, directions: np.ndarray, a: np.ndarray, n: np.ndarray
) -> np.ndarray:
    """Ray parameter t ``(N,)`` where rays meet the plane through ``a (k,)`` with normal ``n (k,)``.

    ``origins``, ``directions``: ``(N, k)``. Either side of the plane counts (planes are
    two-sided). Rays parallel to the plane, and hits at t <= 0, give ``MISS``.
    """
    # BEGIN SOLUTION
    # hint: t = ((a - o)·n) / (d·n); rays parallel to the plane and hits with t <= 0 are MISS
    d_dot_n = directions @ n
    a_minus_o_dot_n = (a - origins) @ n
    with np.errstate(divide="ignore", invalid="ignore"):
        t = a_minus_o_dot_n / d_dot_n
    return np.where((d_dot_n != 0) & (t > 0), t, MISS)
    # END SOLUTION


def hit_points_on_plane(
    origins: np.ndarray, directions: np.ndarray, t: np.ndarray, a: np.ndarray
) -> np.ndarray:
    """The hit points relative to the plane point a, q = (o - a) + t·d, ``(N, k)``.

    Subtracting a before adding t·d keeps the in-plane coordinates accurate when the scene sits
    at large coordinates. Rows with t = MISS hold NaN.
    """
    return (origins - a) + np.where(np.isfinite(t), t, np.nan)[:, None] * directions

"""Ray–plane intersection: the plane through point a with normal n.

A point p lies on the plane when (p - a)·n = 0. Putting in the ray p(t) = o + t·d gives

    t = ((a - o)·n) / (d·n)

(see :mod:`raykit.rays` for the shapes and the miss convention). The difference a - o is taken
first, so a scene far from the origin loses no more digits than its own size forces.

Sides. The slide's plane has a front and a back: a point p is *in front* when p·n > a·n, *on*
the plane when p·n = a·n and *behind* when p·n < a·n (:func:`plane_side`, computed as the sign of
(p - a)·n, the same comparison with the difference taken first). Which side is the front is
the choice of n: -n swaps them.

A normal from three points. Three points a, p, q not on one line fix a plane through a, with
normal n = (p - a) × (q - a) (:func:`normal_from_points`). Normal does not mean normalized: n
is perpendicular to the plane, and its length is twice the area of the triangle a, p, q; the
ray–plane formula and the sides need no unit n (scaling n scales (a - o)·n and d·n alike).
Swapping p and q turns n round, and with it which side is the front.

The same lines serve the line-scan world, where a "plane" is a line with a 2D normal, and the
billboards (:mod:`raykit.billboards`), which are bounded pieces of a plane (n = a × b there).
"""

from __future__ import annotations

import numpy as np

from raykit.rays import MISS, dot


def hit_plane(
    origins: np.ndarray, directions: np.ndarray, a: np.ndarray, n: np.ndarray
) -> np.ndarray:
    """Ray parameter t ``(N,)`` where rays meet the plane through ``a (k,)`` with normal ``n (k,)``.

    ``origins``, ``directions``: ``(N, k)``. Either side of the plane counts (planes are
    two-sided). Rays parallel to the plane, and hits at t <= 0, give ``MISS``.
    """
    # BEGIN SOLUTION
    # hint: t = ((a - o)·n) / (d·n); rays parallel to the plane and hits with t <= 0 are MISS
    d_dot_n = dot(directions, n)
    a_minus_o_dot_n = dot(a - origins, n)
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


def plane_side(p: np.ndarray, a: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Which side of the plane through ``a (k,)`` with normal ``n (k,)`` points ``p (N, k)`` are
    on, ``(N,)`` ints: +1 in front (p·n > a·n), 0 on the plane, -1 behind (p·n < a·n)."""
    # BEGIN SOLUTION
    # hint: p is in front when p·n > a·n, i.e. (p - a)·n > 0; np.sign of (p - a)·n, as integers
    return np.sign(dot(np.asarray(p, float) - a, n)).astype(np.int64)
    # END SOLUTION


def normal_from_points(a: np.ndarray, p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The normal n = (p - a) × (q - a) ``(..., 3)`` of the plane through three points ``a``,
    ``p``, ``q`` ``(..., 3)`` each; not unit length (|n| is twice the triangle's area), and zero
    when the points lie on one line."""
    # BEGIN SOLUTION
    # hint: n = (p - a) × (q - a) (np.cross); do not normalize it
    a = np.asarray(a, float)
    return np.cross(np.asarray(p, float) - a, np.asarray(q, float) - a)
    # END SOLUTION

"""Spheres, and where a ray meets one: the quadratic and its discriminant.

A point p is on the sphere with centre c and radius r when |p - c|² = r². With the ray
p(t) = o + t·d (see :mod:`raykit.rays`) and f = o - c this is the quadratic

    a·t² + 2·b'·t + c' = 0,   a = d·d,   b' = f·d,   c' = f·f - r²,

with discriminant Δ = b'² - a·c'. Δ < 0: the ray misses; Δ = 0: it grazes; Δ > 0: two roots.

The lecture's formula t = (-b' ± √Δ) / a is exact on paper but loses digits in floating point
in two places, and :func:`hit_sphere_textbook` keeps it to show where:

1. Δ itself. For a small sphere far away b'² and a·c' are huge and nearly equal, so their
   difference is mostly rounding error: a ray that misses can "hit" and a ray that hits can
   miss. Haines et al. (Ray Tracing Gems, 2019, ch. 7) rewrite it as

       Δ = a·(r² - |f - (b'/a)·d|²),

   where f - (b'/a)·d is the vector from the centre to the closest point of the ray's line: a
   difference of vectors, small exactly when it matters, with no huge squares cancelling.
2. The root in which -b' and ±√Δ have opposite signs cancels when a·c' ≪ b'². The stable form
   takes only the root without cancellation, q = -(b' + sign(b')·√Δ), and gets the other from
   the product of the roots: t0 = q/a, t1 = c'/q. (When c' is small because the ray starts
   just outside the surface, c' = f·f - r² has itself lost those digits; no root formula can
   win them back, so a ray should not start on a surface: see the t > 0 rule in raykit.rays.)

This module owns the sphere; the 2D line-scan world calls the same function with k = 2 for its
balls (a circle is the 2D sphere).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from raykit.materials import PLAIN, Material
from raykit.rays import MISS, dot, nearest_positive


@dataclass(frozen=True)
class Sphere:
    """A sphere: ``center (3,)``, ``radius > 0``, ``color (3,)`` in [0, 1], and how it answers
    light (:mod:`raykit.materials`; only lit scenes and mirrors use it)."""

    center: np.ndarray
    radius: float
    color: np.ndarray
    name: str | None = None
    material: Material = PLAIN


def sphere_roots(
    origins: np.ndarray, directions: np.ndarray, center: np.ndarray, radius: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both roots and the discriminant of the ray–sphere quadratic, by the stable form.

    Returns ``(t0, t1, discriminant)``, each ``(N,)``; the roots are NaN where the
    discriminant is negative (the ray's line misses), and in no particular order.
    """
    # BEGIN SOLUTION
    # hint: f = o - c, a = d·d, b' = f·d, c' = f·f - r²; Δ = a·(r² - |f - (b'/a)·d|²); q = -(b' +
    #       sign(b')·√Δ), t0 = q/a, t1 = c'/q
    f = origins - center
    a = dot(directions, directions)
    b = dot(f, directions)  # b' = half the textbook b
    c = dot(f, f) - radius * radius
    with np.errstate(divide="ignore", invalid="ignore"):
        closest = f - (b / a)[:, None] * directions  # centre -> closest point on the line
        discriminant = a * (radius * radius - dot(closest, closest))
        q = -(b + np.copysign(np.sqrt(discriminant), b))
        return q / a, c / q, discriminant
    # END SOLUTION


def hit_sphere(
    origins: np.ndarray, directions: np.ndarray, center: np.ndarray, radius: float
) -> np.ndarray:
    """Nearest t > 0 ``(N,)`` where each ray meets the sphere, or ``MISS``; the stable form.

    ``origins``, ``directions``: ``(N, k)``; ``center``: ``(k,)``. A ray starting inside the
    sphere hits its far side.
    """
    # BEGIN SOLUTION
    # hint: the nearest root with t > 0 where the discriminant is >= 0, else MISS (see
    #       raykit.rays.nearest_positive)
    t0, t1, discriminant = sphere_roots(origins, directions, center, radius)
    return np.where(discriminant >= 0, nearest_positive(t0, t1), MISS)
    # END SOLUTION


def sphere_normals(points: np.ndarray, center: np.ndarray, radius) -> np.ndarray:
    """Unit outward normals n = (p - c)/r ``(N, 3)`` at points ``(N, 3)`` on the sphere.

    ``center`` and ``radius``: one sphere's, ``(3,)`` and a number, or each point's own,
    ``(N, 3)`` and ``(N, 1)``. Dividing by r (not by the computed |p - c|) is the book's form:
    p is on the sphere, so |p - c| = r up to rounding.
    """
    # BEGIN SOLUTION
    # hint: n = (p - c) / r: the vector from the centre to the point, made unit length by the
    #       radius
    return (points - center) / radius
    # END SOLUTION


def hit_sphere_textbook(
    origins: np.ndarray, directions: np.ndarray, center: np.ndarray, radius: float
) -> np.ndarray:
    """The lecture's formula, t = (-b' ± √(b'² - a·c')) / a, kept to show where it loses digits.

    Same arguments and result as :func:`hit_sphere`; never used by the renderer.
    """
    f = origins - center
    a = dot(directions, directions)
    b = dot(f, directions)
    c = dot(f, f) - radius * radius
    discriminant = b * b - a * c
    with np.errstate(invalid="ignore"):
        root = np.sqrt(discriminant)
        t = nearest_positive((-b - root) / a, (-b + root) / a)
    return np.where(discriminant >= 0, t, MISS)

"""Spheres, where a ray meets one: the quadratic, its discriminant, the slides' letters (d for r).

A point p is on the sphere with centre c and radius R when (p - c)·(p - c) - R² = 0. With the
ray p(t) = o + t·d (see :mod:`raykit.rays`) this is the lecture's quadratic A·t² + B·t + C = 0,

    A = d·d,   B = 2 d·(o - c),   C = (o - c)·(o - c) - R²,

with discriminant D = B² - 4AC and roots t = (-B ± √D) / 2A. D < 0: the ray misses; D = 0: it
grazes; D > 0: two roots, of which the lower positive one is the hit (:mod:`raykit.rays`: t > 0).

The letter d. The slides write the ray's direction r in the ray, p(t) = o + t r, and in
A = (r · r), but d in the rearranged equation and in B = 2 * d · (o - c): one vector, two
letters. raykit writes d throughout, the direction of :mod:`raykit.rays`.

The letter D. The slides use D twice: here it is the discriminant; in the line-scan camera it is
the distance from the eye to the image line (:mod:`raykit.linescan.camera`). They never meet in
one formula, so raykit keeps the slide's letter in both places and names it in full where the two
could be confused: ``discriminant`` in code, ``camera.D`` for the distance.

The stable form, from the same letters. :func:`hit_sphere_textbook` computes the formula above just
as it stands. It is exact on paper but loses digits in floating point in two places, and
:func:`sphere_roots` (the renderer's) avoids both. Write B = 2b', so b' = d·(o - c) = B/2; then

    D = B² - 4AC = 4(b'² - AC) = 4Δ,   Δ = b'² - AC,   t = (-B ± √D) / 2A = (-b' ± √Δ) / A.

Dividing out the 2s changes no bit (they are powers of two); the digits are lost elsewhere:

1. In D itself. For a small sphere far away b'² and AC are huge and nearly equal, so their
   difference is mostly rounding error: a ray that misses can "hit" and a ray that hits can
   miss. Haines et al. (Ray Tracing Gems, 2019, ch. 7) rewrite it with f = o - c and
   b'/A = (B/2)/A, the t of the point of the ray's line nearest the centre:

       Δ = D/4 = A·(R² - |f - (b'/A)·d|²),

   where f - (b'/A)·d is the vector from the centre to that nearest point: a difference of
   vectors, small exactly when it matters, with no huge squares cancelling. (Expand
   |f - (b'/A)·d|² = f·f - b'²/A and multiply by A: A·R² - A·f·f + b'² = b'² - AC.)
2. In the root where -B and ±√D have opposite signs, which cancels when AC ≪ b'². The stable
   form takes only the root without cancellation, q = -(B + sign(B)·√D)/2 = -(b' +
   sign(b')·√Δ), and gets the other from the product of the roots, t0·t1 = C/A: t0 = q/A,
   t1 = C/q. (When C is small because the ray starts just outside the surface, C has itself
   lost those digits; no root formula can win them back, so a ray should not start on a surface:
   see the t > 0 rule in raykit.rays.)

A moving sphere (motion blur, stage 5): with velocity v, the sphere is at c(T) = c + T·v at time
T (:func:`center_at`), and a ray with its own time T meets the sphere there: the centre is then
one per ray, ``(N, k)``, which every function here takes in place of one ``(k,)``.

This module owns the sphere; the 2D line-scan world calls the same function with k = 2 for its
balls (a circle is the 2D sphere).
"""

from __future__ import annotations

import operator
from collections.abc import Iterator, Sequence
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


class SphereTable(Sequence[Sphere]):
    """Many plain spheres (no name, the plain material) kept as columns: ``centers (S, 3)``,
    ``radii (S,)``, ``colors (S, 3)``, read-only. It reads as the tuple of :class:`Sphere` it
    stands for (``len``, indexing, iterating, ``+``), each Sphere made when asked for. The scene
    loader keeps a file's spheres this way when all are plain (:mod:`raykit.io.scene_json`), so
    that a scene of 600,000 spheres loads without making 600,000 objects, and the engine takes
    the columns as they are (:mod:`raykit.engine.arrays`)."""

    def __init__(self, centers: np.ndarray, radii: np.ndarray, colors: np.ndarray) -> None:
        self.centers, self.radii, self.colors = (
            np.array(x, dtype=float) for x in (centers, radii, colors)
        )
        for column in (self.centers, self.radii, self.colors):
            column.setflags(write=False)  # the spheres handed out share these rows

    def __len__(self) -> int:
        return len(self.radii)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return SphereTable(self.centers[i], self.radii[i], self.colors[i])
        i = operator.index(i)
        return Sphere(self.centers[i], float(self.radii[i]), self.colors[i])

    def __iter__(self) -> Iterator[Sphere]:
        return (self[i] for i in range(len(self)))

    def __add__(self, other: Sequence) -> tuple:
        return tuple(self) + tuple(other)

    def __radd__(self, other: Sequence) -> tuple:
        return tuple(other) + tuple(self)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, SphereTable):
            mine = (self.centers, self.radii, self.colors)
            theirs = (other.centers, other.radii, other.colors)
            return all(map(np.array_equal, mine, theirs))
        return NotImplemented

    __hash__ = None  # as the tuple of Spheres it stands for: numpy fields make them unhashable

    def __repr__(self) -> str:
        return f"SphereTable({len(self)} spheres)"


def sphere_roots(
    origins: np.ndarray, directions: np.ndarray, center: np.ndarray, radius: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both roots and the discriminant of the ray–sphere quadratic, by the stable form.

    ``origins``, ``directions``: ``(N, k)``; ``center``: ``(k,)``, or each ray's own ``(N, k)``
    (a moving sphere, :func:`center_at`). Returns ``(t0, t1,
    discriminant)``, each ``(N,)``, where the discriminant is Δ = D/4 (the module docstring:
    the same sign as D); the roots are NaN where it is negative (the ray's line misses), and
    in no particular order.
    """
    # BEGIN SOLUTION
    # hint: f = o - c, A = d·d, b' = B/2 = f·d, C = f·f - R²; Δ = D/4 = A·(R² - |f - (b'/A)·d|²);
    #       q = -(b' + sign(b')·√Δ), t0 = q/A, t1 = C/q
    f = origins - center
    A = dot(directions, directions)
    b = dot(f, directions)  # b' = B/2
    C = dot(f, f) - radius * radius
    with np.errstate(divide="ignore", invalid="ignore"):
        closest = f - (b / A)[:, None] * directions  # centre -> closest point on the line
        discriminant = A * (radius * radius - dot(closest, closest))  # Δ = D/4
        q = -(b + np.copysign(np.sqrt(discriminant), b))
        return q / A, C / q, discriminant
    # END SOLUTION


def hit_sphere(
    origins: np.ndarray, directions: np.ndarray, center: np.ndarray, radius: float
) -> np.ndarray:
    """Nearest t > 0 ``(N,)`` where each ray meets the sphere, or ``MISS``; the stable form.

    ``origins``, ``directions``: ``(N, k)``; ``center``: ``(k,)``, or each ray's own ``(N, k)``.
    A ray starting inside the sphere hits its far side.
    """
    # BEGIN SOLUTION
    # hint: the nearest root with t > 0 where the discriminant is >= 0, else MISS (see
    #       raykit.rays.nearest_positive)
    t0, t1, discriminant = sphere_roots(origins, directions, center, radius)
    return np.where(discriminant >= 0, nearest_positive(t0, t1), MISS)
    # END SOLUTION


def center_at(center: np.ndarray, velocity: np.ndarray, times: np.ndarray) -> np.ndarray:
    """The centres c(T) = c + T·v ``(N, 3)`` of a sphere with ``center`` c and ``velocity`` v
    ``(3,)`` at the times T ``(N,)`` of N rays (motion blur, :mod:`raykit.sampling`). A stage-5
    student function."""
    # BEGIN SOLUTION
    # hint: one centre per ray, each moved by its own time: c + T·v, with T made a column
    return np.asarray(center, dtype=float) + np.asarray(times, dtype=float)[:, None] * velocity
    # END SOLUTION


def sphere_f(points: np.ndarray, center: np.ndarray, radius) -> np.ndarray:
    """The slide's implicit function of a sphere, f(p) = (p - c)·(p - c) - R², at points
    ``(N, k)``: negative inside, zero on the sphere, positive outside. Putting p(t) = o + t d
    into f(p) = 0 gives the ray–sphere quadratic (:func:`sphere_roots`). Returns ``(N,)``."""
    offset = np.atleast_2d(np.asarray(points, float)) - np.asarray(center, float)
    return dot(offset, offset) - float(radius) ** 2


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
    """The slides' formula, with d for their r (see the module docstring): A = d·d,
    B = 2 d·(o - c), C = (o - c)·(o - c) - R², D = B² - 4AC, t = (-B ± √D) / 2A; of two
    solutions the one with the lower t, which raykit takes among those with t > 0
    (:mod:`raykit.rays`).

    Same arguments and result as :func:`hit_sphere` (``(N, k)`` rays, ``(k,)`` centre, ``t
    (N,)`` or ``MISS``); kept to show where it loses digits, never used by the renderer.
    """
    o_minus_c = origins - center
    A = dot(directions, directions)
    B = 2.0 * dot(directions, o_minus_c)
    C = dot(o_minus_c, o_minus_c) - radius * radius
    D = B * B - 4.0 * A * C  # the discriminant (not the line-scan camera's D)
    with np.errstate(invalid="ignore"):
        root = np.sqrt(D)
        t = nearest_positive((-B - root) / (2.0 * A), (-B + root) / (2.0 * A))
    return np.where(D >= 0, t, MISS)

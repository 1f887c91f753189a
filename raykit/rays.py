"""Rays: p(t) = o + t·d.

Conventions for every intersection routine in raykit (2D and 3D alike)
----------------------------------------------------------------------
* A bundle of N rays is two float64 arrays, ``origins (N, k)`` and ``directions (N, k)``,
  with k = 3 in the 3D renderer and k = 2 in the line-scan world. The math is written once,
  over the last axis, and serves both.
* Directions need not be unit length; the cameras hand out unit directions, so there the
  ray parameter t is also the distance from the ray's origin.
* On the slides a ray is p(t) = o + t·d, t typically non-negative. raykit counts hits only at
  **t > 0**: a hit at exactly t = 0 is a miss, so a ray never hits the surface it starts on (a
  shadow or mirror ray leaving a surface, a line-scan ray starting on a ball). Every
  intersection routine returns ``t (N,)``: the ray parameter of the nearest hit with t > 0, or
  ``MISS`` (+inf) where there is none; a ray that runs parallel to a plane is a miss too.
  (:func:`nearest_positive` is where the rule is applied; tests/test_rays.py pins it.)
* Using +inf for a miss lets "nearest hit wins" be a plain ``<`` comparison and ``np.minimum``.
"""

from __future__ import annotations

import numpy as np

MISS = np.inf


def normalize(vectors: np.ndarray) -> np.ndarray:
    """Scale vectors ``(..., k)`` to unit length along the last axis (zero vectors give NaN)."""
    vectors = np.asarray(vectors, dtype=float)
    squared = dot(vectors, vectors)  # the same bits as np.linalg.norm's sum, in half the time
    with np.errstate(invalid="ignore", divide="ignore"):
        return vectors / np.sqrt(squared)[..., None]


def length(vectors: np.ndarray) -> np.ndarray:
    """The lengths |v| ``(...)`` of vectors ``(..., k)``: the square root of :func:`dot` (v, v),
    so the same bits on every machine (``np.linalg.norm`` of one vector is BLAS's sum)."""
    vectors = np.asarray(vectors, dtype=float)
    return np.sqrt(dot(vectors, vectors))


def dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot product over the last axis: ``(..., k) · (..., k) -> (...)``.

    Summed left to right, a_0·b_0 + a_1·b_1 + ..., with no fused multiply-add: the same bits on
    every machine. (``a @ b`` hands the sum to BLAS, whose order and use of FMA depend on the
    processor, so a picture could change in its last bits from one computer to the next; the
    compiled engine, :mod:`raykit.engine.compiled`, repeats this order exactly.)
    """
    a, b = np.asarray(a), np.asarray(b)
    total = a[..., 0] * b[..., 0]
    for i in range(1, max(a.shape[-1], b.shape[-1])):
        total = total + a[..., i] * b[..., i]
    return total


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product a × b over the last axis: ``(..., 3) × (..., 3) -> (..., 3)``.

    The same products and differences as ``np.cross``, so the same bits, in their dtype; it
    makes them directly where ``np.cross``, for any axis and 2-vectors too, first moves axes
    about, which costs more than the products on the single vectors a scene's load and
    ``prepare`` cross a dozen times.
    """
    a, b = np.asarray(a), np.asarray(b)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    product = np.empty(np.broadcast_shapes(a.shape, b.shape), np.result_type(a, b))
    product[..., 0] = a1 * b2 - a2 * b1
    product[..., 1] = a2 * b0 - a0 * b2
    product[..., 2] = a0 * b1 - a1 * b0
    return product


def point_at(origins: np.ndarray, directions: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The points p(t) = o + t·d, ``(N, k)``; rows where t is not finite give NaN."""
    t = np.asarray(t, dtype=float)
    finite = np.isfinite(t)
    points = origins + np.where(finite, t, 0.0)[..., None] * directions
    points[~finite] = np.nan
    return points


def nearest_positive(t0: np.ndarray, t1: np.ndarray) -> np.ndarray:
    """Per ray, the smaller of two candidate parameters that is > 0, else ``MISS``.

    ``t0`` and ``t1`` ``(N,)`` may hold NaN or ±inf for "no candidate".
    """
    t_near = np.fmin(t0, t1)  # fmin/fmax ignore a NaN partner
    t_far = np.fmax(t0, t1)
    with np.errstate(invalid="ignore"):
        return np.where(t_near > 0, t_near, np.where(t_far > 0, t_far, MISS))

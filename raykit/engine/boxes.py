"""Axis-aligned bounding boxes of objects, and the objects a bundle of ray segments can reach.

A box is its two corners, ``lower`` and ``upper`` ``(3,)``: a sphere's is c ± r, a billboard's
spans its four corners. Boxes are padded a little (``BOX_PADDING``) so that rounding in a test
against a box never drops a ray that the exact intersection would keep. The BVH
(:mod:`raykit.engine.bvh`) is built from them, and :func:`objects_near_segments` uses them to leave
out of a shadow ray's test every object that cannot lie between a point and its light.
"""

from __future__ import annotations

import numpy as np

from raykit.rays import length

BOX_PADDING = 1e-9  # relative to the box's size and distance from the origin


def object_boxes(
    centers: np.ndarray, radii: np.ndarray, billboards
) -> tuple[np.ndarray, np.ndarray]:
    """Padded axis-aligned boxes of K objects, the spheres (``centers (S, 3)``, ``radii (S,)``)
    then the billboards: ``lower``, ``upper (K, 3)``."""
    centers = np.asarray(centers, float).reshape(-1, 3)
    radii = np.asarray(radii, float).reshape(-1, 1)
    lower, upper = [centers - radii], [centers + radii]
    for board in billboards:
        ul = np.asarray(board.upper_left, float)
        a, b = np.asarray(board.a, float), np.asarray(board.b, float)
        corners = np.stack([ul, ul + a, ul + b, ul + a + b])
        lower.append(corners.min(axis=0)[None])
        upper.append(corners.max(axis=0)[None])
    lower, upper = np.concatenate(lower), np.concatenate(upper)
    pad = BOX_PADDING * (
        (upper - lower).max(axis=1, initial=0.0)
        + np.abs(lower).max(axis=1, initial=0.0)
        + np.abs(upper).max(axis=1, initial=0.0)
    )
    return lower - pad[:, None], upper + pad[:, None]


def objects_near_segments(
    boxes: tuple[np.ndarray, np.ndarray],
    origins: np.ndarray,
    directions: np.ndarray,
    t_max: np.ndarray,
) -> np.ndarray:
    """Indices of the objects whose boxes meet the box around the segments o + [0, t_max]·d of
    rays ``(N, 3)`` (``t_max (N,)``, inf: as far as the objects reach). Every object that one of
    the segments can hit is among them."""
    lower, upper = boxes
    if not len(lower) or not len(origins):
        return np.zeros(0, dtype=np.intp)
    scene_lower, scene_upper = lower.min(axis=0), upper.max(axis=0)
    # beyond this, a ray from its origin has left every object's box behind
    corner_distance = length(
        np.maximum(np.abs(origins - scene_lower), np.abs(origins - scene_upper))
    )
    reach = np.minimum(t_max, corner_distance)
    ends = origins + reach[:, None] * directions
    near = np.minimum(origins, ends).min(axis=0)
    far = np.maximum(origins, ends).max(axis=0)
    return np.flatnonzero(np.all((lower <= far) & (upper >= near), axis=1))

"""Repeats :mod:`raykit.hits` for one ray: the nearest hit so far, offered one object more."""

from __future__ import annotations

import numpy as np
from numba import njit

from raykit.engine.compiled.billboards import billboard_color_at, hit_billboard
from raykit.engine.compiled.compiling import INLINED
from raykit.engine.compiled.spheres import hit_sphere


@njit(**INLINED)
def keep_nearer(arrays, obj, o0, o1, o2, d0, d1, d2, best, best_t, r, g, b):
    """Repeats :meth:`raykit.hits.Hits.keep_nearer` for one ray and object ``obj``: the nearest
    hit so far ``(best, best_t, r, g, b)``, replaced by the object's where it is nearer and
    opaque there, or as near and of a lower index (objects may come in any order here; the
    reference offers them in index order, so a tie keeps the lower index)."""
    spheres = len(arrays.radii)
    if obj < spheres:
        centers = arrays.centers
        t = hit_sphere(
            o0, o1, o2, d0, d1, d2, centers[obj, 0], centers[obj, 1], centers[obj, 2],
            arrays.radii[obj],
        )  # fmt: skip
        if t < best_t or (t == best_t and t < np.inf and obj < best):
            colors = arrays.sphere_colors
            return obj, t, colors[obj, 0], colors[obj, 1], colors[obj, 2]
        return best, best_t, r, g, b
    board = obj - spheres
    t, alpha, beta = hit_billboard(o0, o1, o2, d0, d1, d2, arrays, board)
    if t < best_t or (t == best_t and t < np.inf and obj < best):
        cr, cg, cb, opaque = billboard_color_at(arrays, board, alpha, beta)
        if opaque:
            return obj, t, cr, cg, cb
    return best, best_t, r, g, b

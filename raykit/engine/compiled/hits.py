"""Repeats :mod:`raykit.hits` for one ray: the nearest hit so far, offered one object more."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from raykit.engine.compiled.billboards import billboard_color_at, hit_billboard
from raykit.engine.compiled.compiling import INLINED
from raykit.engine.compiled.spheres import hit_sphere


class NearestHit(NamedTuple):
    """The nearest hit of one ray (so far): the object ``index`` (-1: none), ``t`` (inf: none)
    and colour (``r``, ``g``, ``b``: the background where nothing is hit)."""

    index: int
    t: float
    r: float
    g: float
    b: float


@njit(**INLINED)
def keep_nearer(arrays, obj, ray, hit):
    """Repeats :meth:`raykit.hits.Hits.keep_nearer` for one
    :class:`~raykit.engine.compiled.rays.Ray` and object ``obj``: the nearest hit so far
    ``hit`` (a :class:`NearestHit`), replaced by the object's where it is nearer and opaque
    there, or as near and of a lower index (objects may come in any order here; the reference
    offers them in index order, so a tie keeps the lower index)."""
    spheres = len(arrays.radii)
    if obj < spheres:
        centers = arrays.centers
        t = hit_sphere(
            ray.o0, ray.o1, ray.o2, ray.d0, ray.d1, ray.d2,
            centers[obj, 0], centers[obj, 1], centers[obj, 2], arrays.radii[obj],
        )  # fmt: skip
        if t < hit.t or (t == hit.t and t < np.inf and obj < hit.index):
            colors = arrays.sphere_colors
            return NearestHit(index=obj, t=t, r=colors[obj, 0], g=colors[obj, 1], b=colors[obj, 2])
        return hit
    board = obj - spheres
    t, alpha, beta = hit_billboard(ray.o0, ray.o1, ray.o2, ray.d0, ray.d1, ray.d2, arrays, board)
    if t < hit.t or (t == hit.t and t < np.inf and obj < hit.index):
        cr, cg, cb, opaque = billboard_color_at(arrays, board, alpha, beta)
        if opaque:
            return NearestHit(index=obj, t=t, r=cr, g=cg, b=cb)
    return hit

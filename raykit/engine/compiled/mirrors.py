"""Repeats :mod:`raykit.mirrors` and :func:`raykit.shading.shade` for one ray: mirror
bounces up to max_depth, each surface's colour weighted by the mirrors' km on the way."""

from __future__ import annotations

import numpy as np
from numba import njit

from raykit.engine.compiled.bvh import nearest_hit
from raykit.engine.compiled.compiling import INLINED, KERNEL
from raykit.engine.compiled.shading import surface_color
from raykit.engine.compiled.surfaces import surface_point
from raykit.surfaces import OFFSET_FACTOR


@njit(**INLINED)
def bounce_on(arrays, tree, shading, stack, depth, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error,
              c0, c1, c2, w0, w1, w2):  # fmt: skip
    """The rest of :func:`shade_ray` after the surface at ``depth`` (object ``hit`` at p, normal
    n, seen along d, rounding bound ``error``) has added its colour to the pixel's (c0, c1, c2):
    mirror rays (:func:`raykit.mirrors.reflect`, started off the surface) up to max_depth, each
    surface's colour weighted by the mirrors' km on the way (w)."""
    while depth < shading.max_depth and shading.is_mirror[hit]:
        twice = 2.0 * (d0 * n0 + d1 * n1 + d2 * n2)
        d0, d1, d2 = d0 - twice * n0, d1 - twice * n1, d2 - twice * n2
        side = 1.0 if n0 * d0 + n1 * d1 + n2 * d2 >= 0 else -1.0
        offset = side * (OFFSET_FACTOR * error)
        o0, o1, o2 = p0 + offset * n0, p1 + offset * n1, p2 + offset * n2
        km = shading.mirror
        w0, w1, w2 = w0 * km[hit, 0], w1 * km[hit, 1], w2 * km[hit, 2]
        hit, t, r, g, b = nearest_hit(arrays, tree, stack, o0, o1, o2, d0, d1, d2, np.inf)
        depth += 1
        if hit < 0:
            return c0 + w0 * r, c1 + w1 * g, c2 + w2 * b  # the background
        p0, p1, p2, n0, n1, n2, error = surface_point(arrays, shading, o0, o1, o2, d0, d1, d2,
                                                      hit, t)  # fmt: skip
        s0, s1, s2 = surface_color(
            arrays, tree, shading, stack, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error, r, g, b
        )
        c0, c1, c2 = c0 + w0 * s0, c1 + w1 * s1, c2 + w2 * s2
    return c0, c1, c2


@njit(**KERNEL)
def mirror_rays(arrays, tree, shading, stack, lanes, rays, best, made, count, colors):
    """The mirror rays of a job's ``count`` viewing rays ``rays (6, N)`` (origins, then
    directions), each ray that ``made`` a hit on a mirror (object ``best``, at the surface
    point of ``lanes``, :func:`surface_lanes`): :func:`bounce_on` from its colour so far,
    ``colors (3, N)``, weighted 1, into which the result goes. Called once a job, and only for
    a scene with mirrors: the rest of the engine compiles without it."""
    point, normal, error = lanes.p, lanes.n, lanes.error
    for i in range(count):
        hit = best[i]
        if not made[i] or hit < 0 or not shading.is_mirror[hit]:
            continue
        colors[0, i], colors[1, i], colors[2, i] = bounce_on(
            arrays, tree, shading, stack, 0, hit, point[0, i], point[1, i], point[2, i],
            normal[0, i], normal[1, i], normal[2, i], rays[3, i], rays[4, i], rays[5, i],
            error[i], colors[0, i], colors[1, i], colors[2, i], 1.0, 1.0, 1.0,
        )  # fmt: skip


@njit(**KERNEL)
def shade_ray(arrays, tree, shading, stack, o0, o1, o2, d0, d1, d2, hit, t, r, g, b):
    """Repeats :func:`raykit.shading.shade` for one viewing ray and its nearest hit: the surface
    point (:func:`surface_point`), its colour (:func:`surface_color`), and mirror rays up to
    max_depth (:func:`bounce_on`)."""
    if hit < 0:
        return 0.0 + 1.0 * r, 0.0 + 1.0 * g, 0.0 + 1.0 * b  # the background, weighted 1
    p0, p1, p2, n0, n1, n2, error = surface_point(arrays, shading, o0, o1, o2, d0, d1, d2, hit, t)
    s0, s1, s2 = surface_color(
        arrays, tree, shading, stack, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error, r, g, b
    )
    c0, c1, c2 = 0.0 + 1.0 * s0, 0.0 + 1.0 * s1, 0.0 + 1.0 * s2  # weighted 1, added to nothing
    return bounce_on(arrays, tree, shading, stack, 0, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2,
                     error, c0, c1, c2, 1.0, 1.0, 1.0)  # fmt: skip

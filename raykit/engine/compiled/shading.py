"""Repeats :mod:`raykit.shading`: a surface's colour under the lights, for one ray
(:func:`surface_color`) and for a job's rays in lanes (:func:`surface_lanes`,
:func:`light_lanes`), side by side, the same operations in the same order for each ray."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from raykit.engine.compiled.billboards import billboard_color, hit_billboard
from raykit.engine.compiled.bvh import nearest_hit
from raykit.engine.compiled.compiling import INLINED, KERNEL, MAKES_ARRAYS, ONE_RAY
from raykit.engine.compiled.lights import toward_point_light
from raykit.engine.compiled.shadows import point_light_reach
from raykit.engine.compiled.spheres import hit_sphere
from raykit.engine.compiled.surfaces import off_surface, surface_point


@njit(**ONE_RAY)
def highlight(n0, n1, n2, l0, l1, l2, d0, d1, d2, p):
    """Repeats the power in :func:`raykit.shading.blinn_phong`, max(0, n·h)^p with
    h = (l + v)/|l + v| and v = -d, or -1.0 where l + v = 0 (no highlight, as
    :func:`raykit.shading.surface_color` says). The one operation that may differ from the
    reference: the power is the C library's pow here and numpy's own (vectorised) power there;
    they differ by at most one unit in the last place, on a few per cent of highlight points
    (measured), which no 8-bit pixel shows (tests/test_compiled.py bounds it)."""
    v0, v1, v2 = -d0, -d1, -d2
    if not (l0 + v0 != 0 or l1 + v1 != 0 or l2 + v2 != 0):
        return -1.0
    h0, h1, h2 = l0 + v0, l1 + v1, l2 + v2
    length = math.sqrt(h0 * h0 + h1 * h1 + h2 * h2)
    n_dot_h = n0 * (h0 / length) + n1 * (h1 / length) + n2 * (h2 / length)
    return (n_dot_h if n_dot_h > 0 else 0.0) ** p


@njit(**INLINED)
def surface_color(
    arrays, tree, shading, stack, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error, r, g, b
):
    """Repeats :func:`raykit.shading.surface_color` for one hit: object ``hit`` at point p
    with unit normal n, seen along d, its flat colour (r, g, b); ``error`` is the point's
    rounding bound (:func:`surface_point`). Shadow rays (:mod:`raykit.shadows`) walk the tree.
    A tile's viewing rays are shaded in lanes instead (:func:`light_lanes`), the same
    operations in the same order for each."""
    if not shading.lit:
        return r, g, b
    if shading.has_diffuse[hit]:
        k0, k1, k2 = shading.diffuse[hit, 0], shading.diffuse[hit, 1], shading.diffuse[hit, 2]
    else:
        k0, k1, k2 = r, g, b
    ambient = shading.ambient
    total0, total1, total2 = k0 * ambient[0], k1 * ambient[1], k2 * ambient[2]
    vectors, intensity = shading.light_vectors, shading.light_colors
    for j in range(len(shading.point_light)):
        v0, v1, v2 = vectors[j, 0], vectors[j, 1], vectors[j, 2]
        if shading.point_light[j]:  # raykit.lights.toward_light
            l0, l1, l2 = toward_point_light(v0, v1, v2, p0, p1, p2)
        else:
            l0, l1, l2 = v0, v1, v2
        n_dot_l = n0 * l0 + n1 * l1 + n2 * l2
        if not n_dot_l > 0:
            continue
        if shading.shadows:  # raykit.shadows.light_reach and in_shadow
            s0, s1, s2 = off_surface(p0, p1, p2, n0, n1, n2, error)
            reach = point_light_reach(v0, v1, v2, s0, s1, s2) if shading.point_light[j] else np.inf
            _, blocker, _, _, _ = nearest_hit(
                arrays, tree, stack, s0, s1, s2, l0, l1, l2, reach, True
            )
            if blocker < reach:
                continue
        total0 += k0 * intensity[j, 0] * n_dot_l  # raykit.shading.lambert
        total1 += k1 * intensity[j, 1] * n_dot_l
        total2 += k2 * intensity[j, 2] * n_dot_l
        if shading.is_shiny[hit]:
            power = highlight(n0, n1, n2, l0, l1, l2, d0, d1, d2, shading.shininess[hit])
            if power >= 0:  # raykit.shading.blinn_phong
                ks = shading.specular
                total0 += ks[hit, 0] * intensity[j, 0] * power
                total1 += ks[hit, 1] * intensity[j, 1] * power
                total2 += ks[hit, 2] * intensity[j, 2] * power
    return total0, total1, total2


class Lanes(NamedTuple):
    """Room for shading a job's N viewing rays in lanes (:func:`surface_lanes`,
    :func:`light_lanes`), a column per ray: the surface point ``p (3, N)``, its normal ``n (3,
    N)`` and rounding bound ``error (N,)`` (:func:`surface_point`), the colour k that light
    scales ``k (3, N)`` and the colour so far ``total (3, N)``; toward the light at hand, ``l
    (3, N)``, ``n_dot_l (N,)``, the shadow ray's start ``s (3, N)`` and ``reach (N,)``, room
    ``t (N,)``, and whether the light reaches the point, ``lit (N,)``. Each worker makes its
    own inside the parallel loop (:func:`new_lanes`): a NamedTuple passed into a parallel loop
    loses the writes through its fields (numba issue #7135), one made inside it does not."""

    p: np.ndarray
    n: np.ndarray
    error: np.ndarray
    k: np.ndarray
    total: np.ndarray
    l: np.ndarray  # noqa: E741 (the slides' l)
    n_dot_l: np.ndarray
    s: np.ndarray
    reach: np.ndarray
    t: np.ndarray
    lit: np.ndarray


@njit(**MAKES_ARRAYS)
def new_lanes(count):
    """:class:`Lanes` for ``count`` viewing rays."""
    return Lanes(np.empty((3, count)), np.empty((3, count)), np.empty(count),
                 np.empty((3, count)), np.empty((3, count)), np.empty((3, count)),
                 np.empty(count), np.empty((3, count)), np.empty(count), np.empty(count),
                 np.empty(count, dtype=np.bool_))  # fmt: skip


@njit(**KERNEL)
def surface_lanes(arrays, shading, rays, best, best_t, colors, count, lanes, box):
    """The first part of :func:`surface_color` for each of ``count`` viewing rays ``rays (6,
    N)`` (origins, then directions) with a hit (``best`` >= 0, at ``best_t``; flat colours
    ``colors (3, N)``): its surface point, normal and rounding bound (:func:`surface_point`),
    k and the ambient term (in an unlit scene, the flat colour), into ``lanes``; and the box
    of the points into ``box (2, 3)`` (empty: lower > upper). Returns the largest rounding
    bound."""
    p, n, error_of, k, total = lanes.p, lanes.n, lanes.error, lanes.k, lanes.total
    box[0, :], box[1, :] = np.inf, -np.inf
    largest = 0.0
    ambient = shading.ambient
    for i in range(count):
        hit = best[i]
        if hit < 0:  # zeros, not whatever the room held: arithmetic on them is thrown away
            for row in range(3):
                p[row, i], n[row, i] = 0.0, 0.0
            error_of[i] = 0.0
            continue
        p0, p1, p2, n0, n1, n2, error = surface_point(
            arrays, shading, rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i],
            rays[5, i], hit, best_t[i],
        )  # fmt: skip
        p[0, i], p[1, i], p[2, i] = p0, p1, p2
        n[0, i], n[1, i], n[2, i] = n0, n1, n2
        error_of[i] = error
        if shading.has_diffuse[hit]:
            k0, k1, k2 = shading.diffuse[hit, 0], shading.diffuse[hit, 1], shading.diffuse[hit, 2]
        else:
            k0, k1, k2 = colors[0, i], colors[1, i], colors[2, i]
        k[0, i], k[1, i], k[2, i] = k0, k1, k2
        if shading.lit:
            total[0, i] = k0 * ambient[0]
            total[1, i] = k1 * ambient[1]
            total[2, i] = k2 * ambient[2]
        else:  # an unlit scene's surface colour is its flat colour
            total[0, i], total[1, i] = colors[0, i], colors[1, i]
            total[2, i] = colors[2, i]
        box[0, 0], box[1, 0] = min(box[0, 0], p0), max(box[1, 0], p0)
        box[0, 1], box[1, 1] = min(box[0, 1], p1), max(box[1, 1], p1)
        box[0, 2], box[1, 2] = min(box[0, 2], p2), max(box[1, 2], p2)
        largest = max(largest, error)
    return largest


@njit(**KERNEL)  # called once a job: compiled apart, which keeps trace's compile shorter
def light_lanes(arrays, tree, shading, stack, rays, best, count, lanes, candidates, counts):
    """The lights' part of :func:`surface_color` for ``count`` surface points in ``lanes``
    (:func:`surface_lanes`; those of ``best`` >= 0), seen along the directions in ``rays (6,
    N)``, light by light, each step for all points at once: l and n·l; whether the light
    reaches the point (its shadow ray, against light j's ``candidates[j, :counts[j]]``
    (:func:`shadow_lists`), or walking the tree where counts[j] is -1); the Lambert term; the
    highlight. Each point's operations are :func:`surface_color`'s, in its order, so its bits
    are the same; a step that is the same for every point (l, n·l, the start of a shadow ray,
    a sphere or a billboard's plane tested against every shadow ray, the Lambert term, kept or
    not) is one loop the compiler turns into vector instructions, 4 points at a time with
    AVX2 or AVX-512. A point with no hit or facing away from the light takes nothing from them."""
    spheres = len(arrays.radii)
    centers, radii, corners, planes = arrays.centers, arrays.radii, arrays.corners, arrays.n
    p, n, error, k, total = lanes.p, lanes.n, lanes.error, lanes.k, lanes.total
    l, n_dot_l, s, reach, t, lit = lanes.l, lanes.n_dot_l, lanes.s, lanes.reach, lanes.t, lanes.lit
    vectors, intensity = shading.light_vectors, shading.light_colors
    for j in range(len(shading.point_light)):
        v0, v1, v2 = vectors[j, 0], vectors[j, 1], vectors[j, 2]
        if shading.point_light[j]:  # raykit.lights.toward_light; the shadow rays' start and reach
            for i in range(count):
                l[0, i], l[1, i], l[2, i] = toward_point_light(v0, v1, v2, p[0, i], p[1, i],
                                                               p[2, i])  # fmt: skip
                s[0, i], s[1, i], s[2, i] = off_surface(
                    p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error[i]
                )
                reach[i] = point_light_reach(v0, v1, v2, s[0, i], s[1, i], s[2, i])
        else:
            for i in range(count):
                l[0, i], l[1, i], l[2, i] = v0, v1, v2
                s[0, i], s[1, i], s[2, i] = off_surface(
                    p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error[i]
                )
                reach[i] = np.inf
        for i in range(count):
            n_dot_l[i] = n[0, i] * l[0, i] + n[1, i] * l[1, i] + n[2, i] * l[2, i]
            lit[i] = (best[i] >= 0) & (n_dot_l[i] > 0)
        if shading.shadows and counts[j] < 0:  # raykit.shadows.in_shadow, through the tree
            for i in range(count):
                if lit[i]:
                    _, blocker, _, _, _ = nearest_hit(
                        arrays, tree, stack, s[0, i], s[1, i], s[2, i], l[0, i], l[1, i],
                        l[2, i], reach[i], True,
                    )  # fmt: skip
                    lit[i] = not blocker < reach[i]
        elif shading.shadows:  # against the list: a point is dark if any opaque hit is nearer
            for m in range(counts[j]):  # than the light, whichever is nearest
                obj = candidates[j, m]
                if obj < spheres:
                    c0, c1, c2, R = centers[obj, 0], centers[obj, 1], centers[obj, 2], radii[obj]
                    for i in range(count):
                        t[i] = hit_sphere(
                            s[0, i], s[1, i], s[2, i], l[0, i], l[1, i], l[2, i], c0, c1, c2, R
                        )
                    for i in range(count):
                        lit[i] = lit[i] & ~(t[i] < reach[i])
                    continue
                board = obj - spheres  # its plane first, as hit_billboard meets it
                a0, a1, a2 = corners[board, 0], corners[board, 1], corners[board, 2]
                m0, m1, m2 = planes[board, 0], planes[board, 1], planes[board, 2]
                for i in range(count):
                    d_dot_n = l[0, i] * m0 + l[1, i] * m1 + l[2, i] * m2
                    a_minus_o_dot_n = (
                        (a0 - s[0, i]) * m0 + (a1 - s[1, i]) * m1 + (a2 - s[2, i]) * m2
                    )
                    t[i] = a_minus_o_dot_n / d_dot_n
                for i in range(count):  # hit_billboard's t where the plane's is in reach
                    if lit[i] and t[i] > 0 and t[i] < reach[i]:
                        t_hit, alpha, beta = hit_billboard(
                            s[0, i], s[1, i], s[2, i], l[0, i], l[1, i], l[2, i], arrays, board
                        )
                        if t_hit < reach[i] and billboard_color(arrays, board, alpha, beta)[3]:
                            lit[i] = False
        I0, I1, I2 = intensity[j, 0], intensity[j, 1], intensity[j, 2]
        for i in range(count):  # raykit.shading.lambert, where the light reaches
            sum0 = total[0, i] + k[0, i] * I0 * n_dot_l[i]
            sum1 = total[1, i] + k[1, i] * I1 * n_dot_l[i]
            sum2 = total[2, i] + k[2, i] * I2 * n_dot_l[i]
            total[0, i] = sum0 if lit[i] else total[0, i]
            total[1, i] = sum1 if lit[i] else total[1, i]
            total[2, i] = sum2 if lit[i] else total[2, i]
        for i in range(count):  # raykit.shading.blinn_phong
            hit = best[i]
            if not lit[i] or not shading.is_shiny[hit]:
                continue
            power = highlight(n[0, i], n[1, i], n[2, i], l[0, i], l[1, i], l[2, i], rays[3, i],
                              rays[4, i], rays[5, i], shading.shininess[hit])  # fmt: skip
            if power >= 0:
                ks = shading.specular
                total[0, i] += ks[hit, 0] * I0 * power
                total[1, i] += ks[hit, 1] * I1 * power
                total[2, i] += ks[hit, 2] * I2 * power

"""Repeats :mod:`raykit.shading`: a surface's colour under the lights, for one ray
(:func:`surface_color`) and for a job's rays in lanes (:func:`surface_lanes`,
:func:`light_lanes`), side by side, the same operations in the same order for each ray; and
mirror bounces up to max_depth (:func:`shade`, :func:`bounce_on`, :func:`mirror_rays`), each
surface's colour weighted by the mirrors' km on the way."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from raykit.engine.compiled.billboards import billboard_color_at, hit_billboard
from raykit.engine.compiled.bvh import nearest_hit
from raykit.engine.compiled.compiling import INLINED, KERNEL, MAKES_ARRAYS, ONE_RAY
from raykit.engine.compiled.lights import area_intensity, area_light, sampled, toward_point_light
from raykit.engine.compiled.mirrors import glossy_reflect, reflect
from raykit.engine.compiled.sampling import point_on_parallelogram
from raykit.engine.compiled.shadows import point_light_reach
from raykit.engine.compiled.spheres import hit_sphere
from raykit.engine.compiled.surfaces import hit_object, point_and_normal, start, surface_points


@njit(**ONE_RAY)
def lambert(k, I, n_dot_l):  # noqa: E741 (the slides' I)
    """Repeats :func:`raykit.shading.lambert` for one point: kd·I·max(0, n·l), with ``k`` and
    ``I`` (r, g, b) tuples, given n·l (which its caller has computed already, to know whether
    the light faces the point)."""
    facing = 0.0 if n_dot_l <= 0 else n_dot_l  # np.maximum(0.0, n·l), NaN kept
    return k[0] * I[0] * facing, k[1] * I[1] * facing, k[2] * I[2] * facing


@njit(**ONE_RAY)
def blinn_phong(ks, I, n, l, v, p):  # noqa: E741 (the slides' I and l)
    """Repeats :func:`raykit.shading.blinn_phong` for one point: ks·I·max(0, n·h)^p with h = (l +
    v)/|l + v|, each vector and colour a tuple of three (the caller leaves out l + v = 0, as
    :func:`raykit.shading.surface_color` does). The one operation that may differ from the
    reference: the power is the C library's pow here and numpy's own (vectorised) power there; they
    differ by at most one unit in the last place, on a few per cent of highlight points, which no
    8-bit pixel shows (tests/compiled/test_shading.py bounds it)."""
    h0, h1, h2 = l[0] + v[0], l[1] + v[1], l[2] + v[2]
    length = math.sqrt(h0 * h0 + h1 * h1 + h2 * h2)
    n_dot_h = n[0] * (h0 / length) + n[1] * (h1 / length) + n[2] * (h2 / length)
    power = (n_dot_h if n_dot_h > 0 else 0.0) ** p
    return ks[0] * I[0] * power, ks[1] * I[1] * power, ks[2] * I[2] * power


@njit(**INLINED)
def surface_color(scene, stack, hit, p, n, d, error, color, uniforms, depth):
    """Repeats :func:`raykit.shading.surface_color` for one hit of ``scene`` (a
    :class:`~raykit.engine.compiled.scene.CompiledScene`): object ``hit`` at point ``p`` with
    unit normal ``n``, seen along ``d`` (each a tuple of three), its flat ``color`` (r, g, b);
    ``error`` is the point's rounding bound (:func:`surface_points`); ``stack`` is room for a
    tree walk. Shadow rays (:mod:`raykit.shadows`) walk the tree.
    An area light is a point light at this point's own point of it (:func:`sampled`), by the
    ray's sample's uniform numbers ``uniforms (D,)`` for mirror depth ``depth``
    (``shading.light_dims``; empty: at the light's centre). A tile's viewing rays are shaded in
    lanes instead (:func:`light_lanes`), the same operations in the same order for each."""
    arrays, tree, shading = scene
    if not shading.lit:
        return color
    p0, p1, p2 = p
    n0, n1, n2 = n
    d0, d1, d2 = d
    r, g, b = color
    if shading.has_diffuse[hit]:
        k0, k1, k2 = shading.diffuse[hit, 0], shading.diffuse[hit, 1], shading.diffuse[hit, 2]
    else:
        k0, k1, k2 = r, g, b
    ambient = shading.ambient
    total0, total1, total2 = k0 * ambient[0], k1 * ambient[1], k2 * ambient[2]
    vectors, intensity = shading.light_vectors, shading.light_colors
    for j in range(len(shading.point_light)):
        v0, v1, v2 = vectors[j, 0], vectors[j, 1], vectors[j, 2]
        area = shading.area[j]
        if area >= 0:  # raykit.lights.sampled: a point light, where this point's ray aims
            u1, u2 = 0.5, 0.5
            if len(uniforms):
                first = shading.light_dims[depth, area]
                u1, u2 = uniforms[first], uniforms[first + 1]
            v0, v1, v2 = sampled(shading, j, u1, u2)
        distance = np.inf
        if shading.point_light[j]:  # raykit.lights.toward_light
            l0, l1, l2, distance = toward_point_light(v0, v1, v2, p0, p1, p2)
        else:
            l0, l1, l2 = v0, v1, v2
        n_dot_l = n0 * l0 + n1 * l1 + n2 * l2
        if not n_dot_l > 0:
            continue
        if shading.shadows:  # raykit.shadows.light_reach and in_shadow
            s0, s1, s2 = start(p0, p1, p2, n0, n1, n2, error, l0, l1, l2)
            reach = point_light_reach(v0, v1, v2, s0, s1, s2) if shading.point_light[j] else np.inf
            blocker = nearest_hit(arrays, tree, stack, s0, s1, s2, l0, l1, l2, reach, True)
            if blocker.t < reach:
                continue
        I0, I1, I2 = intensity[j, 0], intensity[j, 1], intensity[j, 2]
        if area >= 0:  # raykit.lights.area_intensity: a physically based light's falls off
            I0, I1, I2 = area_intensity(area_light(shading, j), l0, l1, l2, distance)
        a0, a1, a2 = lambert((k0, k1, k2), (I0, I1, I2), n_dot_l)
        total0, total1, total2 = total0 + a0, total1 + a1, total2 + a2
        v0, v1, v2 = -d0, -d1, -d2
        if shading.is_shiny[hit] and (l0 + v0 != 0 or l1 + v1 != 0 or l2 + v2 != 0):
            ks = shading.specular  # no highlight where l + v = 0, as the reference leaves it
            s0, s1, s2 = blinn_phong(
                (ks[hit, 0], ks[hit, 1], ks[hit, 2]), (I0, I1, I2), n, (l0, l1, l2), (v0, v1, v2),
                shading.shininess[hit],
            )  # fmt: skip
            total0, total1, total2 = total0 + s0, total1 + s1, total2 + s2
    return total0, total1, total2


class Lanes(NamedTuple):
    """Room for shading a job's N viewing rays in lanes (:func:`surface_lanes`,
    :func:`light_lanes`), a column per ray: the surface point ``p (3, N)``, its normal ``n (3,
    N)`` and rounding bound ``error (N,)`` (:func:`surface_points`), the colour k that light
    scales ``k (3, N)`` and the colour so far ``total (3, N)``; toward the light at hand, ``l
    (3, N)``, ``n_dot_l (N,)``, the shadow ray's start ``s (3, N)`` and ``reach (N,)``, room
    ``t (N,)``, whether the light reaches the point, ``lit (N,)``, and the intensity it sends
    there, ``intensity (3, N)`` (a physically based area light's, each point's own). Each worker
    has its own, made before its call (:func:`new_lanes`; :func:`~.jobs.lit_rooms`)."""

    p: np.ndarray
    n: np.ndarray
    error: np.ndarray
    k: np.ndarray
    total: np.ndarray
    l: np.ndarray  # FOCG's l, toward the light
    n_dot_l: np.ndarray
    s: np.ndarray
    reach: np.ndarray
    t: np.ndarray
    lit: np.ndarray
    intensity: np.ndarray


@njit(**MAKES_ARRAYS)
def new_lanes(count):
    """:class:`Lanes` for ``count`` viewing rays."""
    return Lanes(np.empty((3, count)), np.empty((3, count)), np.empty(count),
                 np.empty((3, count)), np.empty((3, count)), np.empty((3, count)),
                 np.empty(count), np.empty((3, count)), np.empty(count), np.empty(count),
                 np.empty(count, dtype=np.bool_), np.empty((3, count)))  # fmt: skip


@njit(**KERNEL)
def surface_lanes(arrays, shading, rays, best, best_t, colors, count, lanes, box):
    """The first part of :func:`surface_color` for each of ``count`` viewing rays ``rays (6,
    N)`` (origins, then directions) with a hit (``best`` >= 0, at ``best_t``; flat colours
    ``colors (3, N)``): its surface point, normal and rounding bound (:func:`surface_points`),
    k and the ambient term (in an unlit scene, the flat colour), into ``lanes``; and the box
    of the points into ``box (2, 3)`` (empty: lower > upper). Returns the largest rounding
    bound. What each hit reads of its object (:func:`hit_object`) is read one ray at a time,
    into room that :func:`light_lanes` writes before it reads (``lanes.s`` and ``lanes.t``);
    then the points and normals of all the rays are made in one loop the compiler turns into
    vector instructions (:func:`point_and_normal`)."""
    p, n, error_of, k, total = lanes.p, lanes.n, lanes.error, lanes.k, lanes.total
    held, radius = lanes.s, lanes.t
    ambient = shading.ambient
    for i in range(count):
        hit = best[i]
        if hit < 0:  # numbers for the arithmetic below, which is thrown away
            held[0, i], held[1, i], held[2, i], radius[i] = 0.0, 0.0, 0.0, 0.0
            continue
        held[0, i], held[1, i], held[2, i], radius[i] = hit_object(arrays, shading, hit)
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
    for i in range(count):
        p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error_of[i] = point_and_normal(
            rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i], rays[5, i], best_t[i],
            held[0, i], held[1, i], held[2, i], radius[i],
        )  # fmt: skip
    low0, low1, low2, high0, high1, high2 = np.inf, np.inf, np.inf, -np.inf, -np.inf, -np.inf
    largest = 0.0
    for i in range(count):  # the box in numbers of its own: in box, each step waited on a store
        if best[i] < 0:  # zeros, not whatever the room held: arithmetic on them is thrown away
            for row in range(3):
                p[row, i], n[row, i] = 0.0, 0.0
            error_of[i] = 0.0
            continue
        low0, high0 = min(low0, p[0, i]), max(high0, p[0, i])
        low1, high1 = min(low1, p[1, i]), max(high1, p[1, i])
        low2, high2 = min(low2, p[2, i]), max(high2, p[2, i])
        largest = max(largest, error_of[i])
    box[0, 0], box[0, 1], box[0, 2] = low0, low1, low2
    box[1, 0], box[1, 1], box[1, 2] = high0, high1, high2
    return largest


@njit(**KERNEL)  # called once a job: compiled apart, which keeps trace's compile shorter
def light_lanes(scene, stack, rays, best, count, lanes, candidates, counts, uniforms):
    """The lights' part of :func:`surface_color` for ``count`` surface points in ``lanes``
    (:func:`surface_lanes`; those of ``best`` >= 0), seen along the directions in ``rays (6,
    N)``, light by light, each step for all points at once: l and n·l (toward an area light,
    which only a distributed render has, each ray's own point of it, :func:`sampled`, by its
    uniform numbers, a column of ``uniforms (D, N)``; none elsewhere), and a physically based
    area light's intensity at each point (:func:`area_intensity`); whether the light
    reaches the point (its shadow ray, against light j's ``candidates[j, :counts[j]]``
    (:func:`shadow_lists`), or walking the tree where counts[j] is -1); the Lambert term; the
    highlight. Each point's operations are :func:`surface_color`'s, in its order, so its bits are
    the same; a step that is the same for every point (l, n·l, the start of a shadow ray, a sphere
    or a billboard's plane tested against every shadow ray, the Lambert term, kept or not) is one
    loop the compiler turns into vector instructions, as many points at a time as the processor's
    vectors hold. A point with no hit or facing away from the light takes nothing from them."""
    arrays, tree, shading = scene
    spheres = len(arrays.radii)
    centers, radii, corners, planes = arrays.centers, arrays.radii, arrays.corners, arrays.n
    p, n, error, k, total = lanes.p, lanes.n, lanes.error, lanes.k, lanes.total
    l, n_dot_l, s, reach, t, lit = lanes.l, lanes.n_dot_l, lanes.s, lanes.reach, lanes.t, lanes.lit
    vectors, intensity, each = shading.light_vectors, shading.light_colors, lanes.intensity
    for j in range(len(shading.point_light)):
        v0, v1, v2 = vectors[j, 0], vectors[j, 1], vectors[j, 2]
        area = shading.area[j]
        if area >= 0:  # a point light where each ray aims: raykit.lights.sampled, as sampled
            # repeats it, its edges read before the loop (read in it, they might have been the
            # lanes' own arrays, to the compiler, which then kept the loop one ray at a time)
            first = shading.light_dims[0, area]
            e = shading.light_edges
            e0, e1, e2, e3, e4, e5 = e[j, 0], e[j, 1], e[j, 2], e[j, 3], e[j, 4], e[j, 5]
            light = area_light(shading, j)  # the same: read before the loop
            # two loops, each of which the compiler makes vector instructions (one loop with
            # all of it wrote to more arrays than it checks apart): the point on the light, held
            # in s until the shadow ray's start takes its place
            for i in range(count):
                u1, u2 = uniforms[first, i], uniforms[first + 1, i]
                a0, a1, a2 = point_on_parallelogram(v0, v1, v2, e0, e1, e2, e3, e4, e5, u1, u2)
                l0, l1, l2, distance = toward_point_light(a0, a1, a2, p[0, i], p[1, i], p[2, i])
                l[0, i], l[1, i], l[2, i] = l0, l1, l2
                each[0, i], each[1, i], each[2, i] = area_intensity(light, l0, l1, l2, distance)
                s[0, i], s[1, i], s[2, i] = a0, a1, a2
            for i in range(count):
                a0, a1, a2 = s[0, i], s[1, i], s[2, i]
                s[0, i], s[1, i], s[2, i] = start(
                    p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error[i], l[0, i],
                    l[1, i], l[2, i],
                )  # fmt: skip
                reach[i] = point_light_reach(a0, a1, a2, s[0, i], s[1, i], s[2, i])
        elif shading.point_light[j]:  # raykit.lights.toward_light; the shadow rays' start, reach
            for i in range(count):
                l[0, i], l[1, i], l[2, i], _ = toward_point_light(v0, v1, v2, p[0, i], p[1, i],
                                                                  p[2, i])  # fmt: skip
                s[0, i], s[1, i], s[2, i] = start(
                    p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error[i], l[0, i],
                    l[1, i], l[2, i],
                )  # fmt: skip
                reach[i] = point_light_reach(v0, v1, v2, s[0, i], s[1, i], s[2, i])
        else:
            for i in range(count):
                l[0, i], l[1, i], l[2, i] = v0, v1, v2
                s[0, i], s[1, i], s[2, i] = start(
                    p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error[i], l[0, i],
                    l[1, i], l[2, i],
                )  # fmt: skip
                reach[i] = np.inf
        for i in range(count):
            n_dot_l[i] = n[0, i] * l[0, i] + n[1, i] * l[1, i] + n[2, i] * l[2, i]
            lit[i] = (best[i] >= 0) & (n_dot_l[i] > 0)
        if shading.shadows and counts[j] < 0:  # raykit.shadows.in_shadow, through the tree
            for i in range(count):
                if lit[i]:
                    blocker = nearest_hit(
                        arrays, tree, stack, s[0, i], s[1, i], s[2, i], l[0, i], l[1, i],
                        l[2, i], reach[i], True,
                    )  # fmt: skip
                    lit[i] = not blocker.t < reach[i]
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
                        if t_hit < reach[i] and billboard_color_at(arrays, board, alpha, beta)[3]:
                            lit[i] = False
        I0, I1, I2 = intensity[j, 0], intensity[j, 1], intensity[j, 2]
        falls_off = area >= 0 and shading.physical[j]  # each point its own I
        for i in range(count):  # where the light reaches
            J0 = each[0, i] if falls_off else I0
            J1 = each[1, i] if falls_off else I1
            J2 = each[2, i] if falls_off else I2
            a0, a1, a2 = lambert((k[0, i], k[1, i], k[2, i]), (J0, J1, J2), n_dot_l[i])
            sum0, sum1, sum2 = total[0, i] + a0, total[1, i] + a1, total[2, i] + a2
            total[0, i] = sum0 if lit[i] else total[0, i]
            total[1, i] = sum1 if lit[i] else total[1, i]
            total[2, i] = sum2 if lit[i] else total[2, i]
        for i in range(count):  # the highlight
            hit = best[i]
            if not lit[i] or not shading.is_shiny[hit]:
                continue
            v0, v1, v2 = -rays[3, i], -rays[4, i], -rays[5, i]
            if l[0, i] + v0 != 0 or l[1, i] + v1 != 0 or l[2, i] + v2 != 0:
                ks = shading.specular
                J0, J1, J2 = I0, I1, I2
                if falls_off:
                    J0, J1, J2 = each[0, i], each[1, i], each[2, i]
                s0, s1, s2 = blinn_phong(
                    (ks[hit, 0], ks[hit, 1], ks[hit, 2]), (J0, J1, J2), (n[0, i], n[1, i], n[2, i]),
                    (l[0, i], l[1, i], l[2, i]), (v0, v1, v2), shading.shininess[hit],
                )  # fmt: skip
                total[0, i] += s0
                total[1, i] += s1
                total[2, i] += s2


@njit(**INLINED)
def bounce_on(scene, stack, depth, hit, p, n, d, error, color, weight, uniforms):
    """The rest of :func:`shade` after the surface at ``depth`` (object ``hit`` at ``p``, normal
    ``n``, seen along ``d``, rounding bound ``error``) has added its colour to the pixel's
    ``color`` (each a tuple of three):
    mirror rays (:func:`raykit.engine.compiled.mirrors.reflect`, started off the surface,
    :func:`raykit.engine.compiled.surfaces.start`) up to max_depth, each
    surface's colour weighted by the mirrors' km on the way (``weight``, from the caller's), with
    the ray's ``uniforms``
    (:func:`surface_color`), which also perturb a glossy mirror's ray
    (:func:`raykit.engine.compiled.mirrors.glossy_reflect`) in a scene whose samples take them
    (``shading.gloss_dims``)."""
    arrays, tree, shading = scene
    p0, p1, p2 = p
    n0, n1, n2 = n
    d0, d1, d2 = d
    c0, c1, c2 = color
    w0, w1, w2 = weight
    while depth < shading.max_depth and shading.is_mirror[hit]:
        if len(shading.gloss_dims) and len(uniforms):  # raykit.mirrors.glossy_reflect
            first = shading.gloss_dims[depth]
            d0, d1, d2, above = glossy_reflect(d0, d1, d2, n0, n1, n2, shading.glossiness[hit],
                                               uniforms[first], uniforms[first + 1])  # fmt: skip
            if not above:  # below the surface: absorbed, it reflects nothing
                return c0, c1, c2
        else:
            d0, d1, d2 = reflect(d0, d1, d2, n0, n1, n2)
        o0, o1, o2 = start(p0, p1, p2, n0, n1, n2, error, d0, d1, d2)
        km = shading.mirror
        w0, w1, w2 = w0 * km[hit, 0], w1 * km[hit, 1], w2 * km[hit, 2]
        found = nearest_hit(arrays, tree, stack, o0, o1, o2, d0, d1, d2, np.inf)
        hit, t, r, g, b = found.index, found.t, found.r, found.g, found.b
        depth += 1
        if hit < 0:
            return c0 + w0 * r, c1 + w1 * g, c2 + w2 * b  # the background
        p0, p1, p2, n0, n1, n2, error = surface_points(arrays, shading, o0, o1, o2, d0, d1, d2,
                                                      hit, t)  # fmt: skip
        s0, s1, s2 = surface_color(scene, stack, hit, (p0, p1, p2), (n0, n1, n2), (d0, d1, d2),
                                   error, (r, g, b), uniforms, depth)  # fmt: skip
        c0, c1, c2 = c0 + w0 * s0, c1 + w1 * s1, c2 + w2 * s2
    return c0, c1, c2


@njit(**KERNEL)
def mirror_rays(scene, stack, lanes, rays, best, made, count, colors):
    """The mirror rays of a job's ``count`` viewing rays ``rays (6, N)`` (origins, then
    directions), each ray that ``made`` a hit on a mirror (object ``best``, at the surface
    point of ``lanes``, :func:`surface_lanes`): :func:`bounce_on` from its colour so far,
    ``colors (3, N)``, weighted 1, into which the result goes. Called once a job, and only for
    a scene with mirrors: the rest of the engine compiles without it."""
    point, normal, error = lanes.p, lanes.n, lanes.error
    for i in range(count):
        hit = best[i]
        if not made[i] or hit < 0 or not scene.shading.is_mirror[hit]:
            continue
        colors[0, i], colors[1, i], colors[2, i] = bounce_on(
            scene, stack, 0, hit, (point[0, i], point[1, i], point[2, i]),
            (normal[0, i], normal[1, i], normal[2, i]), (rays[3, i], rays[4, i], rays[5, i]),
            error[i], (colors[0, i], colors[1, i], colors[2, i]), (1.0, 1.0, 1.0), lanes.t[:0],
        )  # fmt: skip


@njit(**INLINED)
def shade(scene, stack, o, d, nearest, uniforms):
    """Repeats :func:`raykit.shading.shade` for one viewing ray of ``scene`` (a
    :class:`~raykit.engine.compiled.scene.CompiledScene`), from ``o`` along ``d`` (tuples of
    three), and its ``nearest`` hit (:class:`~raykit.engine.compiled.hits.NearestHit`): the
    surface point (:func:`surface_points`), its colour (:func:`surface_color`), and mirror rays
    up to max_depth (:func:`bounce_on`); a distributed sample's ``uniforms (D,)`` choose its
    points on the area lights (empty: their centres)."""
    hit, t, r, g, b = nearest.index, nearest.t, nearest.r, nearest.g, nearest.b
    if hit < 0:
        return 0.0 + 1.0 * r, 0.0 + 1.0 * g, 0.0 + 1.0 * b  # the background, weighted 1
    p0, p1, p2, n0, n1, n2, error = surface_points(scene.arrays, scene.shading, o[0], o[1], o[2],
                                                  d[0], d[1], d[2], hit, t)  # fmt: skip
    p, n = (p0, p1, p2), (n0, n1, n2)
    s0, s1, s2 = surface_color(scene, stack, hit, p, n, d, error, (r, g, b), uniforms, 0)
    c0, c1, c2 = 0.0 + 1.0 * s0, 0.0 + 1.0 * s1, 0.0 + 1.0 * s2  # weighted 1, added to nothing
    return bounce_on(scene, stack, 0, hit, p, n, d, error, (c0, c1, c2), (1.0, 1.0, 1.0), uniforms)

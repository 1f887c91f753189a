"""Repeats :mod:`raykit.shadows`: how far a shadow ray's blocker counts, and each tile's
shadow lists, the objects that may lie between what it sees and each light."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types

from raykit.engine.compiled.compiling import INLINED, KERNEL, ONE_RAY
from raykit.engine.compiled.surfaces import EPS
from raykit.surfaces import OFFSET_FACTOR

# ---- shadow rays' skip: each tile's objects that may cast a shadow on what it sees -------------


@njit(**ONE_RAY)
def point_light_reach(v0, v1, v2, s0, s1, s2):
    """Repeats :func:`raykit.shadows.light_reach` for a point light at v and a shadow ray from
    s: how far along the ray a blocker counts."""
    to0, to1, to2 = v0 - s0, v1 - s1, v2 - s2
    distance = math.sqrt(to0 * to0 + to1 * to1 + to2 * to2)
    largest = max(abs(s0), abs(s1), abs(s2))
    return distance - OFFSET_FACTOR * EPS * (largest + distance)


SHADOW_CANDIDATES = 16  # objects a tile lists per light; with more, its shadow rays walk the BVH
DIRECT_LISTS = 96  # objects in a scene up to which the lists test each object, not the tree's
# nodes (both timed on either side by python benchmarks/thresholds.py,
# docs/benchmarks/thresholds.md)
CULL_MARGIN = 1e-9  # of the scene's largest coordinate: rounding that the cull leaves room for


@njit(**ONE_RAY)
def extent(lo0, lo1, lo2, hi0, hi1, hi2, e0, e1, e2):
    """``(lowest, highest)``: where the points of the box lo..hi lie along axis e."""
    x0, x1, y0, y1, z0, z1 = lo0 * e0, hi0 * e0, lo1 * e1, hi1 * e1, lo2 * e2, hi2 * e2
    return min(x0, x1) + min(y0, y1) + min(z0, z1), max(x0, x1) + max(y0, y1) + max(z0, z1)


@njit(**ONE_RAY)
def box_extent(lower, upper, i, e0, e1, e2):
    """:func:`extent` of box i of ``lower``, ``upper (M, 3)``."""
    return extent(
        lower[i, 0], lower[i, 1], lower[i, 2], upper[i, 0], upper[i, 1], upper[i, 2], e0, e1, e2
    )


# box_apart, sphere_apart and candidate run once per object or node a light's list looks at,
# in every job: inlined where they are called, as a test of one ray against an object is
@njit(**INLINED)
def box_apart(volume, lower, upper, i) -> bool:
    """Whether box i (of ``lower``, ``upper (M, 3)``) lies wholly beyond the shadow volume
    along one of its axes (:func:`shadow_volume`): x, y and z first, where a box's extent is
    its own sides."""
    for k in range(3):
        if upper[i, k] < volume[k, 3] or lower[i, k] > volume[k, 4]:
            return True
    for row in range(3, 6):
        low, high = box_extent(lower, upper, i, volume[row, 0], volume[row, 1], volume[row, 2])
        if high < volume[row, 3] or low > volume[row, 4]:
            return True
    return False


@njit(**INLINED)
def sphere_apart(volume, centers, radii, i) -> bool:
    """Whether sphere i lies wholly beyond the shadow volume along one of its axes."""
    R = radii[i]
    for k in range(3):
        if centers[i, k] + R < volume[k, 3] or centers[i, k] - R > volume[k, 4]:
            return True
    for row in range(3, 6):
        c = centers[i, 0] * volume[row, 0] + centers[i, 1] * volume[row, 1]
        c += centers[i, 2] * volume[row, 2]
        if c + R < volume[row, 3] or c - R > volume[row, 4]:
            return True
    return False


@njit(**KERNEL)
def shadow_volume(shading, j, box, pad, scale, volume):
    """Fills ``volume (6, 5)``, rows (e0, e1, e2, lowest, highest): six axes e, and along each
    the interval that holds every shadow ray toward light j from a point of the box ``box (2,
    3)`` (lower and upper corners) widened by ``pad``: a directional light's rays sweep the box
    along l to infinity; a point light's lie in the hull of the box and the light, the light
    too widened by ``pad`` (a ray from s = p + ε·n takes the direction from p, so it passes the
    light at ε from it). The axes: x, y and z
    (in rows 0, 1, 2, as :func:`box_apart` reads them), two across the direction to the light,
    and that direction. The box and each interval are
    widened by CULL_MARGIN x the largest coordinate of the scene (``scale``), the box or the
    light."""
    point = shading.point_light[j]
    vectors = shading.light_vectors
    v0, v1, v2 = vectors[j, 0], vectors[j, 1], vectors[j, 2]
    largest = scale
    for k in range(3):  # (scalars: an array expression here would allocate, once per tile)
        largest = max(largest, abs(box[0, k]), abs(box[1, k]))
    if point:
        largest = max(largest, abs(v0), abs(v1), abs(v2))
    margin = CULL_MARGIN * largest
    lo0, lo1, lo2 = box[0, 0] - pad - margin, box[0, 1] - pad - margin, box[0, 2] - pad - margin
    hi0, hi1, hi2 = box[1, 0] + pad + margin, box[1, 1] + pad + margin, box[1, 2] + pad + margin
    if point:  # from the box's centre toward the light
        m0, m1, m2 = v0 - (lo0 + hi0) / 2, v1 - (lo1 + hi1) / 2, v2 - (lo2 + hi2) / 2
    else:
        m0, m1, m2 = v0, v1, v2
    length = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
    if not length > 0:  # any axis separates as truly; this one only less tightly
        m0, m1, m2, length = 1.0, 0.0, 0.0, 1.0
    m0, m1, m2 = m0 / length, m1 / length, m2 / length
    if abs(m0) < 0.6:  # a, b across m: m x (1, 0, 0), or m x (0, 1, 0) if m is near x; m x a
        a0, a1, a2 = 0.0, m2, -m1
    else:
        a0, a1, a2 = -m2, 0.0, m0
    length = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    a0, a1, a2 = a0 / length, a1 / length, a2 / length
    b0, b1, b2 = m1 * a2 - m2 * a1, m2 * a0 - m0 * a2, m0 * a1 - m1 * a0
    axes = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (a0, a1, a2), (b0, b1, b2),
            (m0, m1, m2))  # fmt: skip
    for row in range(6):
        e0, e1, e2 = axes[row]
        low, high = extent(lo0, lo1, lo2, hi0, hi1, hi2, e0, e1, e2)
        toward = v0 * e0 + v1 * e1 + v2 * e2
        if point:
            low, high = min(low, toward - pad), max(high, toward + pad)
        elif row != 3 and row != 4 and toward > 0:  # along l the rays go on for ever
            high = np.inf
        elif row != 3 and row != 4 and toward < 0:
            low = -np.inf
        volume[row, 0], volume[row, 1], volume[row, 2] = e0, e1, e2
        volume[row, 3], volume[row, 4] = low - margin, high + margin


@njit(**ONE_RAY)
def candidate(arrays, tree, volume, obj, candidates, j, count) -> int:
    """Adds object ``obj`` to light j's ``candidates`` unless it is apart from the shadow volume
    (a sphere: itself; a billboard: its box): the new count, or -1 past SHADOW_CANDIDATES."""
    if obj < len(arrays.radii):
        apart = sphere_apart(volume, arrays.centers, arrays.radii, obj)
    else:
        apart = box_apart(volume, tree.object_lower, tree.object_upper, obj)
    if apart:
        return count
    if count == SHADOW_CANDIDATES:
        return -1
    candidates[j, count] = obj
    return count + 1


@njit(locals={"count": types.int64}, **KERNEL)  # not the literal 0: one signature of candidate
def shadow_candidates(arrays, tree, volume, nodes, candidates, j) -> int:
    """Light j's candidates: the objects whose boxes (a sphere: itself) are not apart from the
    shadow volume (:func:`shadow_volume`), into ``candidates[j]``; returns how many, or -1 if
    more than SHADOW_CANDIDATES (then the shadow rays walk the tree themselves). In a scene of
    DIRECT_LISTS objects or fewer each object is tested; in a larger one, the tree is walked,
    leaving every node whose box is apart. ``nodes (STACK,)``."""
    objects = len(tree.order)
    count = 0
    if objects <= DIRECT_LISTS:
        for obj in range(objects):
            count = candidate(arrays, tree, volume, obj, candidates, j, count)
            if count < 0:
                return -1
        return count
    nodes[0] = 0
    top = 1
    while top > 0:
        top -= 1
        node = nodes[top]
        if box_apart(volume, tree.lower, tree.upper, node):
            continue
        if tree.children[node, 0] >= 0:
            nodes[top], nodes[top + 1] = tree.children[node, 1], tree.children[node, 0]
            top += 2
            continue
        for k in range(tree.first[node], tree.first[node] + tree.count[node]):
            count = candidate(arrays, tree, volume, tree.order[k], candidates, j, count)
            if count < 0:
                return -1
    return count


@njit(**KERNEL)
def shadow_lists(arrays, tree, shading, stack, box, pad, volume, candidates, counts):
    """Each light j's :func:`shadow_candidates` for the shadow rays from the surface points in
    ``box (2, 3)`` (lower, upper corners; empty if lower > upper), which start within ``pad``
    of them, into ``candidates[j]`` (L x
    SHADOW_CANDIDATES) and ``counts (L,)``, with room for a shadow volume ``volume (6, 5)``.

    Why the answers stay the reference's. A point is in shadow if some opaque hit lies before
    the light (:func:`raykit.shadows.in_shadow`): whichever object gives it, the answer is the
    same, so an object may be left out if no shadow ray can hit it. A ray from a point of the
    box toward light j lies in its volume (:func:`shadow_volume`), and where the reference finds
    a hit is a point of the ray and, up to rounding, of the object: that rounding, a few units
    in the last place of the scene's coordinates, is a millionth of the margin the volume is
    widened by, so an object the volume is apart from is never hit."""
    counts[:] = -1
    if not box[0, 0] <= box[1, 0] or len(tree.order) == 0:
        return
    scale = 0.0  # the largest coordinate of the root box
    for k in range(3):
        scale = max(scale, abs(tree.lower[0, k]), abs(tree.upper[0, k]))
    nodes, _ = stack
    for j in range(len(counts)):
        shadow_volume(shading, j, box, pad, scale, volume)
        counts[j] = shadow_candidates(arrays, tree, volume, nodes, candidates, j)

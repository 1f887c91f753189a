"""Repeats :mod:`raykit.engine.bvh`'s walk of the tree for one ray: the nearest hit
(:func:`raykit.render.cast`) of a shadow or mirror ray, nearer child first."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from raykit.engine.compiled.compiling import INLINED, MAKES_ARRAYS
from raykit.engine.compiled.hits import NearestHit, keep_nearer
from raykit.engine.compiled.rays import Ray

STACK = 128  # nodes a ray may have still to visit: a median-split tree of 2^63 objects is 63 deep


# objects in a scene up to which a shadow or mirror ray tests each object, not the tree's
# boxes: timed on either side by python benchmarks/thresholds.py (docs/benchmarks/thresholds.md)
DIRECT_HITS = 8


@njit(**INLINED)
def enters(o0, o1, o2, i0, i1, i2, lower, upper, node, t_max):
    """Repeats the slab test of :mod:`raykit.engine.bvh` (``_enters``) for one ray with inverse
    direction (i0, i1, i2): ``(entered, near)``, whether it enters the box by t_max, and where."""
    near = -np.inf
    far = np.inf
    for axis, o, i in ((0, o0, i0), (1, o1, i1), (2, o2, i2)):
        t1 = (lower[node, axis] - o) * i
        t2 = (upper[node, axis] - o) * i
        if math.isnan(t1) or math.isnan(t2):
            continue  # a ray parallel to a slab, starting on its face: the slab is open
        near = max(near, min(t1, t2))
        far = min(far, max(t1, t2))
    return far >= near and far >= 0 and near <= t_max, near


@njit(**INLINED)
def nearest_hit(arrays, tree, stack, o0, o1, o2, d0, d1, d2, t_max, any_blocker=False):
    """Repeats :func:`raykit.render.cast` for one ray, through the BVH: a
    :class:`~raykit.engine.compiled.hits.NearestHit`,
    the nearest opaque hit with t > 0 (the lower index on a tie), or (-1, inf, background).
    Hits at t > t_max may be left out (shadow rays). In a scene of :data:`DIRECT_HITS` objects
    or fewer each object is tested, as if all were one leaf, and no box is. ``any_blocker``:
    a shadow ray asks only whether some opaque hit lies before t_max
    (:func:`raykit.shadows.in_shadow` compares the nearest hit's t with it), so the search
    stops at the first such hit, whose t < t_max answers as the nearest's would. ``stack``:
    room for the nodes still to visit and where the ray enters them, ``(STACK,)`` ints and
    floats (:func:`new_stack`), reused from ray to ray. A child's box is tested once, when its
    parent is left, and skipped when taken from the stack if the nearest hit found meanwhile
    lies before it: the nodes visited are those a test at each visit would visit, with one slab
    test fewer per node."""
    background = arrays.background
    # int64, not the literal -1: a kernel given the hit (surface_points) is typed for it once
    hit = NearestHit(index=np.int64(-1), t=np.inf, r=background[0], g=background[1],
                     b=background[2])  # fmt: skip
    objects = len(tree.order)  # the tree holds each of the scene's objects once
    if objects == 0:
        return hit
    ray = Ray(o0=o0, o1=o1, o2=o2, d0=d0, d1=d1, d2=d2)
    lower, upper = tree.lower, tree.upper
    nodes, nears = stack
    if objects <= DIRECT_HITS:  # no box is tested: the inverse direction, three divisions,
        i0, i1, i2 = 0.0, 0.0, 0.0  # would be made for nothing
        nodes[0], nears[0] = -1, -np.inf  # -1: every object, as one leaf with no box
    else:
        i0, i1, i2 = 1.0 / d0, 1.0 / d1, 1.0 / d2  # ±inf along an axis the ray does not move
        entered, near = enters(o0, o1, o2, i0, i1, i2, lower, upper, 0, t_max)
        if not entered:
            return hit
        nodes[0], nears[0] = 0, near
    top = 1
    while top > 0:  # each node on the stack was entered, at nears[top]
        top -= 1
        node = nodes[top]
        reach = min(hit.t, t_max)
        if nears[top] > reach:
            continue  # a box that starts beyond the nearest hit holds no nearer one
        if node < 0:
            first, count = 0, objects
        else:
            left = tree.children[node, 0]
            if left >= 0:
                right = tree.children[node, 1]
                in_left, near_left = enters(o0, o1, o2, i0, i1, i2, lower, upper, left, reach)
                in_right, near_right = enters(o0, o1, o2, i0, i1, i2, lower, upper, right, reach)
                if in_left and in_right:  # the nearer child is searched first: pushed last
                    if near_left <= near_right:
                        nodes[top], nears[top] = right, near_right
                        nodes[top + 1], nears[top + 1] = left, near_left
                    else:
                        nodes[top], nears[top] = left, near_left
                        nodes[top + 1], nears[top + 1] = right, near_right
                    top += 2
                elif in_left:
                    nodes[top], nears[top] = left, near_left
                    top += 1
                elif in_right:
                    nodes[top], nears[top] = right, near_right
                    top += 1
                continue
            first, count = tree.first[node], tree.count[node]
        # one call site for keep_nearer: LLVM inlines it at each (INLINED), so a second loop
        # for DIRECT_HITS would make its code twice
        for k in range(first, first + count):
            hit = keep_nearer(arrays, tree.order[k], ray, hit)
            if any_blocker and hit.t < t_max:
                return hit
    return hit


@njit(**MAKES_ARRAYS)
def new_stack():
    """Room for :func:`nearest_hit`'s nodes still to visit: ``(nodes (STACK,), nears (STACK,))``."""
    return np.empty(STACK, dtype=np.int64), np.empty(STACK)

"""Ray–object pairs: each ray's nearest hit among the objects paired with it, all at once.

The skipping structures decide which objects a ray *might* hit and hand over (ray, object)
pairs: the BVH (:mod:`raykit.engine.bvh`) from the boxes a ray passes through, a crowded tile
(:mod:`raykit.engine.tiles`) from the objects whose screen rectangle holds the ray's pixel. Here
every pair is intersected in one go: all sphere pairs in one call of
:func:`raykit.spheres.hit_sphere` (each pair with its own centre and radius), billboard pairs
one billboard at a time, holes in textures let through. Then each ray keeps its nearest hit,
the lower object index on a tie: exactly what :func:`raykit.render.cast` answers when the pairs
include every object a ray hits.
"""

from __future__ import annotations

import numpy as np

from raykit.billboards import billboard_color_at, hit_billboard
from raykit.engine.arrays import SceneArrays
from raykit.rays import MISS
from raykit.scene import Scene
from raykit.spheres import hit_sphere


def nearest_of_pairs(
    scene: Scene,
    arrays: SceneArrays,
    origins: np.ndarray,
    directions: np.ndarray,
    ray: np.ndarray,
    obj: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per ray ``(N, 3)``, the nearest hit among the objects paired with it (pairs
    ``ray``, ``obj`` ``(P,)``): ``index (N,)`` (-1 none), ``t (N,)``, ``color (N, 3)``
    (undefined where nothing is hit). Ties go to the lower object index, as in cast."""
    t = np.full(len(ray), MISS)
    board_color = np.empty((len(ray), 3))  # written only at billboard pairs
    spheres = len(scene.spheres)
    on_sphere = np.flatnonzero(obj < spheres)
    if len(on_sphere):
        centers, radii = arrays.centers, arrays.radii
        which, rays = obj[on_sphere], ray[on_sphere]
        t[on_sphere] = hit_sphere(origins[rays], directions[rays], centers[which], radii[which])
    for i in np.unique(obj[obj >= spheres]):
        pairs = np.flatnonzero(obj == i)
        rays = ray[pairs]
        board_t, alpha, beta = hit_billboard(
            origins[rays], directions[rays], scene.billboards[i - spheres]
        )
        inside = np.flatnonzero(np.isfinite(board_t))
        colors, opaque = billboard_color_at(scene.billboards[i - spheres], alpha, beta)(inside)
        t[pairs[inside[opaque]]] = board_t[inside[opaque]]
        board_color[pairs[inside]] = colors
    # Per ray the smallest t, then among the pairs at that t the lowest object index: each
    # (ray, object) pair is there once, so that pair is the winner.
    nearest_t = np.full(len(origins), MISS)
    np.minimum.at(nearest_t, ray, t)
    at_nearest = np.flatnonzero(np.isfinite(t) & (t == nearest_t[ray]))
    lowest = np.full(len(origins), np.iinfo(np.int64).max)
    np.minimum.at(lowest, ray[at_nearest], obj[at_nearest])
    first = at_nearest[obj[at_nearest] == lowest[ray[at_nearest]]]
    index = np.full(len(origins), -1)
    index[ray[first]] = obj[first]
    nearest_color = np.empty((len(origins), 3))
    sphere_won = obj[first] < spheres  # a sphere's colour is looked up only where it wins
    nearest_color[ray[first[sphere_won]]] = arrays.sphere_colors[obj[first[sphere_won]]]
    nearest_color[ray[first[~sphere_won]]] = board_color[first[~sphere_won]]
    return index, nearest_t, nearest_color

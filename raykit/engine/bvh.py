"""A bounding volume hierarchy: each ray tests only the objects whose boxes it passes through.

Primary rays can skip hidden objects by screen position (:mod:`raykit.engine.tiles`), but shadow and
mirror rays start anywhere and go anywhere, so they need a structure in the scene itself. A BVH
is a binary tree of axis-aligned boxes: each node's box holds all of its objects, a leaf holds
at most ``LEAF_SIZE`` objects. A ray that misses a node's box cannot hit anything inside it, so
its whole subtree is skipped; in a scene of K objects a ray visits about log2(K) levels.

Build: the objects' boxes (sphere: c ± r; billboard: its four corners), split at the median of
their centres along the axis where the centres spread most.

Traverse, for many rays at once: a list of (ray, node) pairs, starting with every ray at the
root. Each round tests all pairs' boxes in one go (the slab test below), keeps the pairs whose
ray enters the box, and replaces them by (ray, child) pairs, until only leaves are left; then
every (ray, object) pair of those leaves is intersected with the same functions ``cast`` uses,
and each ray keeps its nearest hit, the lower object index on a tie. So
:meth:`BVH.cast` answers exactly what :func:`raykit.render.cast` answers, only faster on scenes
with many objects (tests check both).

Slab test: the ray o + t·d is inside the box lo..hi for t in [max_i t_near,i, min_i t_far,i],
with t_near,i, t_far,i the sorted (lo_i - o_i)/d_i, (hi_i - o_i)/d_i. It enters the box if
that interval is not empty and not all behind it. Boxes are padded a little so that rounding in
this test never drops a ray that the exact intersection would keep.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from raykit.engine.arrays import SceneArrays
from raykit.engine.pairs import nearest_of_pairs
from raykit.hits import Hits
from raykit.scene import Scene

LEAF_SIZE = 4
RAYS_PER_CHUNK = 8192  # bounds the memory of (ray, object) pairs


@dataclass(frozen=True)
class BVH:
    """The tree as arrays over its M nodes: box corners ``lower``, ``upper (M, 3)``;
    ``children (M, 2)`` (-1 for a leaf); a leaf's objects are ``order[first:first + count]``;
    ``arrays``, the scene's (:mod:`raykit.engine.arrays`)."""

    scene: Scene
    arrays: SceneArrays
    lower: np.ndarray
    upper: np.ndarray
    children: np.ndarray
    first: np.ndarray
    count: np.ndarray
    order: np.ndarray

    @classmethod
    def build(cls, scene: Scene, arrays: SceneArrays | None = None) -> BVH:
        arrays = arrays or SceneArrays.of(scene)
        lower, upper = arrays.boxes
        return cls(scene, arrays, *_median_split_tree(lower, upper))

    def candidates(
        self, origins: np.ndarray, directions: np.ndarray, t_max: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The (ray, object) pairs ``(P,)`` each whose ray enters a leaf box holding the object
        (before ``t_max (N,)``, if given)."""
        if not len(self.order):
            return np.zeros(0, np.intp), np.zeros(0, np.intp)
        with np.errstate(divide="ignore"):
            inverse = 1.0 / directions
        ray = np.arange(len(origins))
        node = np.zeros(len(origins), dtype=np.intp)
        t_max = np.full(len(origins), np.inf) if t_max is None else np.asarray(t_max, float)
        leaf_rays, leaf_nodes = [], []
        while len(ray):
            enters = _enters(
                origins[ray], inverse[ray], self.lower[node], self.upper[node], t_max[ray]
            )
            ray, node = ray[enters], node[enters]
            leaf = self.children[node, 0] < 0
            leaf_rays.append(ray[leaf])
            leaf_nodes.append(node[leaf])
            ray = np.repeat(ray[~leaf], 2)
            node = self.children[node[~leaf]].ravel()
        ray, node = np.concatenate(leaf_rays), np.concatenate(leaf_nodes)
        counts = self.count[node]
        pair_ray = np.repeat(ray, counts)
        starts = np.repeat(self.first[node] - np.cumsum(counts) + counts, counts)
        return pair_ray, self.order[starts + np.arange(len(pair_ray))]

    def cast(
        self, origins: np.ndarray, directions: np.ndarray, t_max: np.ndarray | None = None
    ) -> Hits:
        """The nearest hit of each ray ``(N, 3)``: the same as :func:`raykit.render.cast`.
        With ``t_max (N,)``, boxes entered only beyond it are skipped, so hits at t > t_max may
        be reported as misses."""
        hits = Hits.none(len(origins), self.scene.background)
        for start in range(0, len(origins), RAYS_PER_CHUNK):
            part = slice(start, start + RAYS_PER_CHUNK)
            limit = None if t_max is None else t_max[part]
            index, t, color = self._nearest(origins[part], directions[part], limit)
            hits.index[part], hits.t[part] = index, t
            found = index >= 0
            hits.color[part][found] = color[found]
        return hits

    def _nearest(self, origins, directions, t_max):
        ray, obj = self.candidates(origins, directions, t_max)
        return nearest_of_pairs(self.scene, self.arrays, origins, directions, ray, obj)


def _enters(origins, inverse, lower, upper, t_max) -> np.ndarray:
    """``(N,)`` bool: does each ray (origin, 1/direction) enter its box at some t in
    [0, t_max]?"""
    with np.errstate(invalid="ignore"):
        t1 = (lower - origins) * inverse
        t2 = (upper - origins) * inverse
        # NaN is 0·inf: a ray parallel to a slab starting on its face; count the slab as open
        near = np.where(np.isnan(t1) | np.isnan(t2), -np.inf, np.minimum(t1, t2)).max(axis=1)
        far = np.where(np.isnan(t1) | np.isnan(t2), np.inf, np.maximum(t1, t2)).min(axis=1)
    return (far >= near) & (far >= 0) & (near <= t_max)


def _median_split_tree(lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, ...]:
    """The tree over K boxes ``lower``, ``upper (K, 3)``, built a level at a time: each node
    not yet a leaf (more than LEAF_SIZE objects) is split at the median of its objects' centres
    along the axis where they spread most (ties in order of object index). Every node of a level
    is split at once with numpy, so a scene of 600,000 objects builds in a fraction of a second
    (one node at a time took seconds). Returns :class:`BVH`'s arrays, nodes numbered level by
    level from the root (0): ``lower``, ``upper``, ``children``, ``first``, ``count``, ``order``."""
    K = len(lower)
    if K == 0:
        return (np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 2), np.intp),
                np.zeros(0, np.intp), np.zeros(0, np.intp), np.zeros(0, np.intp))  # fmt: skip
    centres = (lower + upper) / 2
    rank = np.empty((3, K), dtype=np.intp)  # each object's place along each axis, ties by index
    for axis in range(3):
        rank[axis, np.argsort(centres[:, axis], kind="stable")] = np.arange(K)
    most = 2 * K  # a binary tree with K or fewer leaves
    node_lower, node_upper = np.empty((most, 3)), np.empty((most, 3))
    children = np.full((most, 2), -1, dtype=np.intp)
    first, count = np.zeros(most, np.intp), np.zeros(most, np.intp)
    order = np.arange(K)  # each node's objects are order[start:start + size]
    nodes, starts, sizes = np.array([0]), np.array([0]), np.array([K])  # this level's
    made = 1
    while len(nodes):
        offsets = np.cumsum(sizes) - sizes  # each node's place among this level's objects
        node_of = np.repeat(np.arange(len(nodes)), sizes)
        positions = np.repeat(starts - offsets, sizes) + np.arange(sizes.sum())
        objects = order[positions]
        node_lower[nodes] = np.minimum.reduceat(lower[objects], offsets)
        node_upper[nodes] = np.maximum.reduceat(upper[objects], offsets)
        first[nodes], count[nodes] = starts, sizes
        split = sizes > LEAF_SIZE
        spread = np.maximum.reduceat(centres[objects], offsets) - np.minimum.reduceat(
            centres[objects], offsets
        )
        axis = np.argmax(spread, axis=1)  # the first of equal spreads, as np.argmax picks
        inner = split[node_of]
        key = node_of[inner] * K + rank[axis[node_of[inner]], objects[inner]]
        order[positions[inner]] = objects[inner][np.argsort(key, kind="stable")]
        count[nodes[split]] = 0
        half = sizes[split] // 2
        left = made + 2 * np.arange(len(half))
        children[nodes[split]] = np.column_stack([left, left + 1])
        made += 2 * len(half)
        nodes = np.column_stack([left, left + 1]).ravel()
        starts = np.column_stack([starts[split], starts[split] + half]).ravel()
        sizes = np.column_stack([half, sizes[split] - half]).ravel()
    first[:made][children[:made, 0] >= 0] = 0  # an inner node holds no objects itself
    return (node_lower[:made], node_upper[:made], children[:made], first[:made],
            count[:made], order)  # fmt: skip

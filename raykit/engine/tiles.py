"""Tiles: each square of pixels is tested only against the objects that can be seen in it.

The renderer (:func:`raykit.render.render`) walks the image region by region and calls the
same ``cast`` on each. Without skipping, a region is a band of whole rows and sees every object.
With skipping (the default), a region is a ``TILE`` x ``TILE`` square and sees only the objects
whose screen bounds (:mod:`raykit.engine.screen_bounds`) overlap it, in their scene order, so the
nearest hit and the tie rule are the same as with every object: the bounds are conservative.
``index_of`` maps a region's object numbers back to the scene's (and -1 to -1).

Within a tile, :meth:`Region.holding` tells which objects' screen rectangles hold each image
point. The renderer (:mod:`raykit.engine.regions`) makes no ray for a point that no rectangle
holds: it sees the background, as its ray would. A crowded tile (``CROWDED`` objects or more,
as in a sphereflake) goes one step further: each of its rays is paired only with the objects
whose rectangle holds its point, and all pairs are intersected at once (:mod:`raykit.engine.pairs`),
instead of every ray of the tile meeting every object of the tile.

``holding`` defines these (object, point) pairs as a ``(K, N)`` table; the renderer finds the
same pairs without the table, by binary search on the tile's pixel grid
(:meth:`Region.pairs_on_grid`) or, for the scattered points of adaptive sampling, by sorting the
points into their pixels (:meth:`Region.pairs_at`).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from raykit.engine.arrays import SceneArrays
from raykit.engine.screen_bounds import scene_bounds
from raykit.scene import Scene

TILE = 128  # pixels a side: bigger tiles pay less per-tile overhead, and rays are made only
# where some object may be seen, so their extra area costs little
CROWDED = 8  # objects in a tile from which its rays are paired with objects by screen rectangle
# (both chosen among candidates by python benchmarks/thresholds.py,
# docs/benchmarks/thresholds.md)
RAYS_PER_BAND = 1 << 16  # without skipping: bounds memory, big enough to keep numpy busy


@dataclass(frozen=True)
class Region:
    """Pixels ``rows`` x ``cols`` of the image, the scene as seen there, ``index_of``, the whole
    scene, and the screen rectangles ``bounds (K, 4)`` of the objects seen (None: no skipping)."""

    rows: range
    cols: range
    scene: Scene
    index_of: np.ndarray
    whole: Scene
    bounds: np.ndarray | None = None

    @cached_property
    def covered(self) -> bool:
        """True when some object's screen rectangle holds the whole region, so that every
        image point in it may see an object. Regions with skipping only (``bounds`` given)."""
        with np.errstate(invalid="ignore"):  # NaN bounds: never visible
            return bool(
                (
                    (self.bounds[:, 0] <= self.cols.start)
                    & (self.bounds[:, 1] >= self.cols.stop)
                    & (self.bounds[:, 2] <= self.rows.start)
                    & (self.bounds[:, 3] >= self.rows.stop)
                ).any()
            )

    def holding(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Which of the region's objects have a screen rectangle holding each image point
        (x, y) ``(N,)``: ``(K, N)`` bool. Regions with skipping only (``bounds`` given)."""
        bounds = self.bounds
        with np.errstate(invalid="ignore"):  # NaN bounds: never visible
            return (
                (bounds[:, 0:1] <= x)
                & (x <= bounds[:, 1:2])
                & (bounds[:, 2:3] <= y)
                & (y <= bounds[:, 3:4])
            )

    def pairs_on_grid(self, a: float = 0.5, b: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
        """The (object, point) pairs ``(P,)`` each, whose object's screen rectangle holds the
        point, for the region's own pixels sampled at offset (a, b), numbered row-major as
        :func:`raykit.camera.region_points` makes them: the pairs ``np.nonzero(holding(x,
        y))`` gives, in the same order, without the ``(K, N)`` table. Each rectangle covers
        a block of the grid, found by binary search on the grid's x and y."""
        xs = np.asarray(self.cols, dtype=float) + a
        ys = np.asarray(self.rows, dtype=float) + b
        bounds = self.bounds
        left, right = (
            np.searchsorted(xs, bounds[:, 0], "left"),
            np.searchsorted(xs, bounds[:, 1], "right"),
        )
        top, bottom = (
            np.searchsorted(ys, bounds[:, 2], "left"),
            np.searchsorted(ys, bounds[:, 3], "right"),
        )
        width, height = np.maximum(right - left, 0), np.maximum(bottom - top, 0)
        count = width * height  # points in each object's block (NaN bounds: none)
        which = np.repeat(np.arange(len(bounds)), count)
        k = _counting_within(count)
        point = (top[which] + k // width[which]) * len(xs) + left[which] + k % width[which]
        return which, point

    def pairs_at(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The (object, point) pairs ``(P,)`` each whose object's screen rectangle holds the
        point, for any image points (x, y) ``(N,)`` in the region's pixels (as adaptive
        sampling casts them): the pairs of ``np.nonzero(holding(x, y))``, grouped by object,
        without the ``(K, N)`` table. The points are sorted by the pixel they fall in; each
        rectangle takes, for each row of pixels it meets, the run of points in its pixels
        there, and keeps the points it holds."""
        width, height = len(self.cols), len(self.rows)
        column = np.clip(np.floor(x).astype(np.intp) - self.cols.start, 0, width - 1)
        row = np.clip(np.floor(y).astype(np.intp) - self.rows.start, 0, height - 1)
        cell = row * width + column
        order = np.argsort(cell, kind="stable")  # pixel c holds points order[first[c]:first[c+1]]
        first = np.searchsorted(cell[order], np.arange(width * height + 1))
        visible = ~np.isnan(self.bounds).any(axis=1)
        bounds = np.nan_to_num(self.bounds)
        left, right = (
            np.clip(np.floor(bounds[:, i]).astype(np.intp) - self.cols.start, 0, width - 1)
            for i in (0, 1)
        )
        top, bottom = (
            np.clip(np.floor(bounds[:, i]).astype(np.intp) - self.rows.start, 0, height - 1)
            for i in (2, 3)
        )
        runs = np.where(visible, bottom - top + 1, 0)  # per rectangle, the pixel rows it meets
        which = np.repeat(np.arange(len(bounds)), runs)
        run_row = top[which] + _counting_within(runs)
        begin = first[run_row * width + left[which]]
        length = first[run_row * width + right[which] + 1] - begin
        which = np.repeat(which, length)
        point = order[np.repeat(begin, length) + _counting_within(length)]
        x0, x1, y0, y1 = self.bounds[which].T
        held = (x0 <= x[point]) & (x[point] <= x1) & (y0 <= y[point]) & (y[point] <= y1)
        return which[held], point[held]

    @property
    def pixels(self) -> tuple[slice, slice]:
        return slice(self.rows.start, self.rows.stop), slice(self.cols.start, self.cols.stop)


def _counting_within(counts: np.ndarray) -> np.ndarray:
    """0, 1, ..., count - 1 for each of the ``counts (M,)``, one after the other:
    ``(counts.sum(),)``, each element's place within its own block."""
    return np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)


def regions(
    scene: Scene,
    skip_hidden: bool = True,
    arrays: SceneArrays | None = None,
    rays_per_band: int = RAYS_PER_BAND,
) -> Iterator[Region]:
    """The regions that cover the image, each with the objects it must test (``arrays``: the
    scene's, if made already); without skipping, bands of about ``rays_per_band`` pixels."""
    camera = scene.camera
    width, height = camera.width, camera.height
    everything = np.append(np.arange(scene.object_count), -1)
    if not skip_hidden:
        rows_per_band = max(1, rays_per_band // width)
        for top in range(0, height, rows_per_band):
            rows = range(top, min(top + rows_per_band, height))
            yield Region(rows, range(width), scene, everything, scene)
        return
    arrays = arrays or SceneArrays.of(scene)
    bounds = scene_bounds(camera, arrays.centers, arrays.radii, scene.billboards)  # (K, 4)
    for top in range(0, height, TILE):
        for left in range(0, width, TILE):
            rows = range(top, min(top + TILE, height))
            cols = range(left, min(left + TILE, width))
            with np.errstate(invalid="ignore"):  # NaN bounds: never visible
                overlap = (
                    (bounds[:, 0] <= cols.stop)
                    & (bounds[:, 1] >= cols.start)
                    & (bounds[:, 2] <= rows.stop)
                    & (bounds[:, 3] >= rows.start)
                )
            ids = np.flatnonzero(overlap)
            yield Region(rows, cols, scene.only(ids), np.append(ids, -1), scene, bounds[ids])

"""Adaptive supersampling: extra rays only where the picture changes.

With flat colours, a pixel whose eight neighbours all show exactly its colour lies inside one
object (or one texel): more rays would find the same colour again. So the renderer first takes
one ray per pixel, then casts the n x n samples only for *edge* pixels, those with a neighbour of
another colour or another object, and keeps the centre colour everywhere else. That skips the
extra rays of the flat areas, which are most of an image.

What it can miss: a detail smaller than a pixel that no pixel centre reaches (a far thin
sphere between centres) stays invisible, as it is at one ray per pixel.

In a lit scene (:mod:`raykit.shading`) colours change smoothly across a surface, so most lit
pixels differ a little from a neighbour and count as edges: adaptive sampling stays correct
there but saves little.
"""

from __future__ import annotations

import numpy as np

from raykit.camera import sample_offsets

POINTS_PER_CALL = 1 << 14  # image points per call of ``colors``: one call pays the renderer's
# fixed cost once for many samples, and a bounded batch keeps its arrays small enough to stay
# in cache (chosen by python benchmarks/thresholds.py, docs/benchmarks/thresholds.md)


def edge_pixels(rgb: np.ndarray, object_index: np.ndarray) -> np.ndarray:
    """``(H, W)`` bool: pixels with a 3x3 neighbour of another colour or object."""
    height, width = object_index.shape
    key = np.concatenate([rgb, object_index[..., None].astype(float)], axis=-1)
    padded = np.pad(key, ((1, 1), (1, 1), (0, 0)), mode="edge")
    edge = np.zeros((height, width), dtype=bool)
    for dy in range(3):
        for dx in range(3):
            edge |= (padded[dy : dy + height, dx : dx + width] != key).any(axis=-1)
    return edge


def refine(regions, colors, rgb: np.ndarray, edge: np.ndarray, samples: int, progress=None) -> int:
    """Replace the colour of every edge pixel by the mean of its n x n samples, in place.

    ``regions`` are the renderer's (:mod:`raykit.engine.tiles`), so each tile's edge pixels are
    tested only against the objects seen there; ``colors(region, x, y)`` gives the renderer's
    colours ``(N, 3)`` of the rays through image points (x, y) ``(N,)``. It is called with many
    samples of a tile's edge pixels at once, up to ``POINTS_PER_CALL``, so the renderer's fixed
    cost per call is not paid n² times. Returns how many pixels were supersampled.
    ``progress``, if given, is called with each tile's pixel count as the tile is done.
    """
    a, b = sample_offsets(samples).T
    for region in regions:
        rows, cols = np.nonzero(edge[region.pixels])
        if len(rows):
            _refine_tile(
                region, rows + region.rows.start, cols + region.cols.start, colors, rgb, a, b
            )
        if progress is not None:
            progress(len(region.rows) * len(region.cols))
    return int(edge.sum())


def _refine_tile(region, rows, cols, colors, rgb, a, b) -> None:
    """The edge pixels (rows, cols) of one tile: their n x n samples' mean, in place."""
    total = np.zeros((len(rows), 3))
    per_call = max(1, POINTS_PER_CALL // len(rows))  # sample offsets per call
    for start in range(0, len(a), per_call):
        offsets = slice(start, start + per_call)
        x = (cols + a[offsets, None]).ravel()  # (offsets, M) flattened, offset by offset
        y = (rows + b[offsets, None]).ravel()
        for colors_at_offset in colors(region, x, y).reshape(-1, len(rows), 3):
            total += colors_at_offset  # in offset order, as the full render sums
    rgb[rows, cols] = total / len(a)

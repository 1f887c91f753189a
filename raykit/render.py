"""The renderer: for every pixel, the nearest object its ray hits, and that object's colour.

This is the lecture's loop, "for each pixel: make its ray, find the nearest hit, copy the
colour of the object at that point", run for all pixels of a region at once (numpy arrays
instead of a per-pixel Python loop). A region is a tile of pixels with only the objects that can
be seen in it, so hidden objects cost nothing (:mod:`raykit.tiles`, which names what it skips).
Conventions: pixels and rays per :mod:`raykit.camera`,
object indices per :mod:`raykit.scene`, colours are linear floats in [0, 1] with no gamma.

Colour. A scene without lights, ambient light or mirrors (every scene of format v1) shows each
object's flat colour, and nothing else runs. Otherwise each sample's hit is shaded
(:mod:`raykit.shading`): its shadow and mirror rays go through the whole scene, by brute force
over every object (``cast`` itself) in small scenes, or through a bounding volume hierarchy
(:mod:`raykit.bvh`) from ``BVH_FROM`` objects on, which skips the objects a ray's path misses.

With n x n samples per pixel (:func:`raykit.camera.sample_offsets`), the pixel's colour is the
mean of its samples' colours, taken before quantising to 8 bits (:mod:`raykit.images`). The
``object_index`` and ``t`` images always describe the ray through the pixel *centre*.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np

from raykit.adaptive import edge_pixels, refine
from raykit.billboards import billboard_color_at, hit_billboard
from raykit.boxes import objects_near_segments
from raykit.bvh import BVH
from raykit.camera import rays_through, region_points, sample_offsets
from raykit.hits import Hits, solid
from raykit.pairs import nearest_of_pairs
from raykit.precision import eye_relative
from raykit.scene import Scene
from raykit.shading import needs_shading, shade
from raykit.shadows import Caster
from raykit.spheres import hit_sphere
from raykit.tiles import CROWDED, Region, regions

BVH_FROM = 24  # objects: below this, brute force was faster for secondary rays (measured)


@dataclass(frozen=True)
class Render:
    """A rendered image: ``rgb (H, W, 3)`` float in [0, 1]; for the ray through each pixel
    centre, ``object_index (H, W)`` int (-1 for the background) and hit distance ``t (H, W)``
    (inf for the background)."""

    rgb: np.ndarray
    object_index: np.ndarray
    t: np.ndarray


def cast(scene: Scene, origins: np.ndarray, directions: np.ndarray) -> Hits:
    """The nearest hit of each ray ``(N, 3)`` over all objects of the scene."""
    # BEGIN SOLUTION
    # hint: start from Hits.none, then offer every sphere and every billboard, in index order, to
    #       Hits.keep_nearer
    hits = Hits.none(len(origins), scene.background)
    for i, sphere in enumerate(scene.spheres):
        t = hit_sphere(origins, directions, sphere.center, sphere.radius)
        hits.keep_nearer(i, t, solid(sphere.color))
    for i, billboard in enumerate(scene.billboards, start=len(scene.spheres)):
        t, alpha, beta = hit_billboard(origins, directions, billboard)
        hits.keep_nearer(i, t, billboard_color_at(billboard, alpha, beta))
    return hits
    # END SOLUTION


def cast_pixels(
    scene: Scene, rows: np.ndarray, cols: np.ndarray
) -> tuple[np.ndarray, np.ndarray, Hits]:
    """The rays through the centres of pixels (rows, cols) ``(N,)`` and their nearest hits:
    ``origins (N, 3)``, ``directions (N, 3)`` and :class:`raykit.hits.Hits`. The same rays,
    and the same hits, as the pixel centres of :func:`render`."""
    origins, directions = rays_through(
        scene.camera, np.asarray(cols, float) + 0.5, np.asarray(rows, float) + 0.5
    )
    return origins, directions, cast(scene, origins, directions)


def secondary_caster(scene: Scene) -> Caster:
    """The nearest-hit function for shadow and mirror rays over the whole scene: ``cast`` over
    the objects the rays can reach, or a BVH's for scenes of ``BVH_FROM`` objects or more (the
    same answers)."""
    if len(scene.objects) < BVH_FROM:
        return partial(cast_nearby, scene)
    return BVH.build(scene).cast


def cast_nearby(
    scene: Scene, origins: np.ndarray, directions: np.ndarray, t_max: np.ndarray | None = None
) -> Hits:
    """``cast`` over only the objects whose boxes meet the box around the rays' segments up to
    ``t_max (N,)`` (:func:`raykit.boxes.objects_near_segments`): shadow rays of a tile toward a
    light skip what lies elsewhere. Hits at t >= t_max may be left out."""
    if t_max is None:
        t_max = np.full(len(origins), np.inf)
    near = objects_near_segments(scene.boxes, origins, directions, t_max)
    if len(near) == len(scene.objects):
        return cast(scene, origins, directions)
    hits = cast(scene.only(near), origins, directions)
    hits.index = np.append(near, -1)[hits.index]
    return hits


def render(
    scene: Scene,
    samples: int = 1,
    *,
    skip_hidden: bool = True,
    adaptive: bool = False,
    dtype: type = np.float64,
    progress: Callable[[int], object] | None = None,
) -> Render:
    """Render ``scene`` with ``samples`` x ``samples`` rays per pixel.

    ``skip_hidden``: test each tile of pixels only against the objects that can be seen in it
    (:mod:`raykit.tiles`); the image is the same either way, only the time differs.
    ``adaptive``: take the n x n samples only in pixels at an edge (:mod:`raykit.adaptive`).
    ``dtype``: ``np.float32`` intersects in single precision, the scene moved to the eye first
    (:mod:`raykit.precision`); the default float64 uses the scene as it is.
    ``progress``: called with each tile's pixel count as the tile is finished (width x height
    in all; with ``adaptive``, as the tile's edge pixels are refined); a progress bar's update.
    """
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    if dtype != np.float64:
        scene = eye_relative(scene, dtype)
    if adaptive and samples > 1:
        first = render(scene, 1, skip_hidden=skip_hidden, dtype=dtype)
        edge = edge_pixels(first.rgb, first.object_index)
        secondary = secondary_caster(scene) if needs_shading(scene) else None
        refine(
            regions(scene, skip_hidden),
            lambda region, x, y: _colors(scene, region, x, y, dtype, secondary)[1],
            first.rgb,
            edge,
            samples,
            progress,
        )
        return first
    secondary = secondary_caster(scene) if needs_shading(scene) else None
    camera = scene.camera
    height, width = camera.height, camera.width
    rgb = np.zeros((height, width, 3))
    object_index = np.empty((height, width), dtype=np.int64)
    t_image = np.empty((height, width))
    offsets = sample_offsets(samples)
    centre_sample = samples // 2 * (samples + 1) if samples % 2 else None  # (0.5, 0.5)

    for region in regions(scene, skip_hidden):
        shape = (len(region.rows), len(region.cols))
        pixels = region.pixels
        for k, (a, b) in enumerate(offsets):
            x, y = region_points(region.rows, region.cols, a, b)
            hits, colors = _colors(scene, region, x, y, dtype, secondary, grid=(a, b))
            rgb[pixels] += colors.reshape(*shape, 3)
            if k == centre_sample:
                object_index[pixels] = hits.index.reshape(shape)
                t_image[pixels] = hits.t.reshape(shape)
        if centre_sample is None:  # even n: no sample sits at the centre, so cast one there
            x, y = region_points(region.rows, region.cols)
            hits, _ = _colors(scene, region, x, y, dtype, None, grid=(0.5, 0.5))
            object_index[pixels] = hits.index.reshape(shape)
            t_image[pixels] = hits.t.reshape(shape)
        if progress is not None:
            progress(shape[0] * shape[1])

    rgb /= len(offsets)
    return Render(rgb, object_index, t_image)


def cast_region(
    region: Region,
    origins: np.ndarray,
    directions: np.ndarray,
    pairs: tuple[np.ndarray, np.ndarray] | None = None,
) -> Hits:
    """The nearest hits of a region's rays ``(N, 3)``, with the scene's object indices:
    ``cast`` over the region's objects or, given ``pairs`` (region object, ray) ``(P,)`` each,
    only those pairs, all at once (:mod:`raykit.pairs`): the same hits if the pairs hold every
    object each ray can hit."""
    if pairs is None:
        hits = cast(region.scene, origins, directions)
        hits.index = region.index_of[hits.index]
        return hits
    which, ray = pairs
    index, t, color = nearest_of_pairs(
        region.whole, origins, directions, ray, region.index_of[which]
    )
    hits = Hits.none(len(origins), region.whole.background)
    found = index >= 0
    hits.index[found], hits.t[found], hits.color[found] = index[found], t[found], color[found]
    return hits


def _colors(
    scene: Scene,
    region: Region,
    x: np.ndarray,
    y: np.ndarray,
    dtype: type,
    secondary: Caster | None,
    grid: tuple[float, float] | None = None,
) -> tuple[Hits, np.ndarray]:
    """The nearest hits of the rays through image points (x, y) ``(N,)`` (scene object
    indices), and their colours ``(N, 3)``: flat, or shaded when ``secondary`` (the whole
    scene's caster) is given. ``grid`` (a, b): the points are the region's pixels sampled at
    offset (a, b), row-major, which finds the objects that may be seen at each point faster.

    With skipping, rays are made only for the image points that some object's screen
    rectangle holds: the others see the background, which is what their rays would find (the
    rectangles are conservative), so skipping them changes no pixel. A crowded tile
    (:data:`raykit.tiles.CROWDED` objects or more) pairs each ray only with the objects whose
    rectangle holds its point."""
    seen, pairs = _seen_and_pairs(region, x, y, grid)
    if seen is None:  # every ray can hit something
        origins, directions = _rays(scene.camera, x, y, dtype)
        hits = cast_region(region, origins, directions, pairs)
        if secondary is None:
            return hits, hits.color
        return hits, shade(scene, secondary, origins, directions, hits)
    hits = Hits.none(len(x), scene.background)
    colors = hits.color.copy()
    if not seen.any():
        return hits, colors
    origins, directions = _rays(scene.camera, x[seen], y[seen], dtype)
    seen_hits = cast_region(region, origins, directions, pairs)
    hits.index[seen], hits.t[seen] = seen_hits.index, seen_hits.t
    hits.color[seen] = seen_hits.color
    if secondary is None:
        colors[seen] = seen_hits.color
    else:
        colors[seen] = shade(scene, secondary, origins, directions, seen_hits)
    return hits, colors


def _seen_and_pairs(
    region: Region, x: np.ndarray, y: np.ndarray, grid: tuple[float, float] | None
) -> tuple[np.ndarray | None, tuple[np.ndarray, np.ndarray] | None]:
    """Which image points (x, y) ``(N,)`` some object's screen rectangle holds (``(N,)`` bool,
    None for all), and in a crowded region the (object, ray) pairs to intersect, rays numbered
    among the seen ones (None: every ray meets every object of the region)."""
    if region.bounds is None or (len(region.bounds) < CROWDED and region.covered):
        return None, None
    which, ray = region.pairs_on_grid(*grid) if grid else region.pairs_at(x, y)
    seen = np.zeros(len(x), dtype=bool)
    seen[ray] = True
    pairs = (which, ray) if len(region.bounds) >= CROWDED else None
    if seen.all():
        return None, pairs
    if pairs is not None:
        pairs = which, (np.cumsum(seen) - 1)[ray]  # rays numbered among the seen ones
    return seen, pairs


def _rays(camera, x: np.ndarray, y: np.ndarray, dtype: type) -> tuple[np.ndarray, np.ndarray]:
    """The camera's rays through (x, y), made in float64 and then given to ``dtype``."""
    origins, directions = rays_through(camera, x, y)
    return origins.astype(dtype, copy=False), directions.astype(dtype, copy=False)

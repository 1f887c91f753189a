"""The renderer's machinery: which pixels, which rays, against which objects.

:func:`raykit.render.render` reads as the lecture's loop; this module is what it stands on. A
:class:`Plan` walks the image region by region (:mod:`raykit.engine.tiles`) and, within a
region, sample offset by sample offset; each step is a :class:`Batch` of image points. For a
batch it makes the viewing rays only for the points that some object's screen rectangle holds
(the others see the background, which is what their rays would find: the rectangles are
conservative), finds their nearest hits with ``cast`` over the region's objects, or in a
crowded tile (:data:`raykit.engine.tiles.CROWDED` objects or more) over (object, ray) pairs by
screen rectangle (:mod:`raykit.engine.pairs`), and stores colours, object indices and t in the
image. None of it changes a pixel: ``skip_hidden=False`` gives the same image the plain way.

Shadow and mirror rays cannot use the screen tiles. :func:`secondary_caster` gives them ``cast``
over only the objects whose boxes meet their segments (:mod:`raykit.engine.boxes`) in small
scenes, or a bounding volume hierarchy (:mod:`raykit.engine.bvh`) from ``BVH_FROM`` objects on.

A distributed render (stage 5, :attr:`raykit.scene.Scene.distributed`) takes the scene's
samples per pixel instead of the n x n grid: sample k of every pixel of a region is one batch,
its image points and its choices on the lens and the area lights made from the sample's uniform
numbers (:mod:`raykit.engine.noise`), which depend on the seed, the pixel and k only, never on
the region. With a lens, rays no longer start at the eye, so the screen rectangles bound
nothing: such a render tests every object (as ``skip_hidden=False`` does). With spheres moving
in the shutter interval (:attr:`raykit.scene.Scene.moving`) neither the screen rectangles nor
the boxes of the objects as they stand bound where the rays find them: every ray, primary,
shadow or mirror, is tested against every object at its own time (``cast(..., times=)``). The
rays' times of a region are made for all its pixels' samples at once
(:func:`raykit.sampling.shutter_times` takes a pixel's samples together), in bands of at most
``TIMES_PER_BAND`` numbers.

Conventions: pixels, samples and rays per :mod:`raykit.camera`; object indices per
:mod:`raykit.scene`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import partial

import numpy as np

from raykit.camera import (
    centre_sample,
    rays_through,
    region_points,
    sample_offsets,
    thin_lens_rays,
)
from raykit.engine.arrays import SceneArrays
from raykit.engine.boxes import objects_near_segments
from raykit.engine.bvh import BVH
from raykit.engine.noise import Dimensions, PixelSamples
from raykit.engine.pairs import nearest_of_pairs
from raykit.engine.precision import eye_relative
from raykit.engine.tiles import CROWDED, RAYS_PER_BAND, Region, regions
from raykit.hits import Hits
from raykit.sampling import point_in_pixel, shutter_times
from raykit.scene import Scene
from raykit.shading import needs_shading
from raykit.shadows import Caster

BVH_FROM = 96  # objects from which shadow and mirror rays walk a BVH, not every object they
# can reach: timed on either side by python benchmarks/thresholds.py
# (docs/benchmarks/thresholds.md)
TIMES_PER_BAND = 1 << 20  # a motion-blurred band's ray times (pixels x samples): bounds memory

# cast(scene, origins (N, 3), directions (N, 3)) -> Hits: the lecture's nearest hit over every
# object of a scene (raykit.render.cast); the engine only chooses which scene to give it
SceneCaster = Callable[[Scene, np.ndarray, np.ndarray], Hits]


def secondary_caster(scene: Scene, cast: SceneCaster, arrays: SceneArrays | None = None) -> Caster:
    """The nearest-hit function for shadow and mirror rays over the whole scene: ``cast`` over
    the objects the rays can reach, or a BVH's for scenes of ``BVH_FROM`` objects or more (the
    same answers)."""
    if scene.moving:
        return partial(cast_at_times, scene, cast)
    arrays = arrays or SceneArrays.of(scene)
    if scene.object_count < BVH_FROM:
        return partial(cast_nearby, scene, arrays, cast)
    return BVH.build(scene, arrays).cast


def cast_at_times(
    scene: Scene,
    cast: SceneCaster,
    origins: np.ndarray,
    directions: np.ndarray,
    t_max: np.ndarray | None = None,
    times: np.ndarray | None = None,
) -> Hits:
    """``cast`` over every object, each ray at its own time ``times (N,)`` (a scene whose
    spheres move: no box of them as they stand bounds where a ray finds them)."""
    return cast(scene, origins, directions, times=times)


def cast_nearby(
    scene: Scene,
    arrays: SceneArrays,
    cast: SceneCaster,
    origins: np.ndarray,
    directions: np.ndarray,
    t_max: np.ndarray | None = None,
) -> Hits:
    """``cast`` over only the objects whose boxes meet the box around the rays' segments up to
    ``t_max (N,)`` (:func:`raykit.engine.boxes.objects_near_segments`): shadow rays of a tile
    toward a light skip what lies elsewhere. Hits at t >= t_max may be left out."""
    if t_max is None:
        t_max = np.full(len(origins), np.inf)
    near = objects_near_segments(arrays.boxes, origins, directions, t_max)
    if len(near) == scene.object_count:
        return cast(scene, origins, directions)
    hits = cast(scene.only(near), origins, directions)
    hits.index = np.append(near, -1)[hits.index]
    return hits


def refuse_grid(scene: Scene, samples: int) -> None:
    """A one-line ValueError for n x n ``samples`` other than 1 of a distributed scene, which
    takes its samples from its own ``render.samples_per_pixel``."""
    if scene.distributed and samples != 1:
        raise ValueError(
            f"{scene.source}: a distributed scene takes its samples from "
            f"render.samples_per_pixel, not from the n x n grid (samples {samples})"
        )


@dataclass(frozen=True)
class Batch:
    """Image points (x, y) ``(N,)`` of one region: its pixels at one sample offset ``grid``
    (row-major), or scattered points (``grid`` None). ``centre``: this batch's hits are the
    ones the image keeps per pixel (the ray through the pixel centre); ``colour``: its colours
    count towards the pixel's mean (False for a centre batch cast only for the hits)."""

    region: Region
    x: np.ndarray
    y: np.ndarray
    grid: tuple[float, float] | None
    centre: bool = False
    colour: bool = True
    finishes: int = 0  # pixels of the region done once this batch is stored (its last batch)
    uniforms: np.ndarray | None = None  # a distributed sample's numbers (N, dimensions)
    times: np.ndarray | None = None  # its rays' times (N,) in a scene that moves


class Plan:
    """How one render goes: the scene (moved to the eye in float32), its regions and samples,
    the caster of its shadow and mirror rays; see the module docstring."""

    def __init__(
        self,
        scene: Scene,
        cast: SceneCaster,
        samples: int = 1,
        *,
        skip_hidden: bool = True,
        dtype: type = np.float64,
        progress: Callable[[int], object] | None = None,
        hits: bool = True,
    ) -> None:
        self.scene = eye_relative(scene, dtype) if dtype != np.float64 else scene
        self.cast = cast
        self.samples = samples
        self.offsets = sample_offsets(samples)  # (n*n, 2); refuses n < 1 before any work
        self.sample_count = len(self.offsets)  # colours summed per pixel
        self.pixel_samples = None  # a distributed render's uniform numbers
        if scene.distributed:
            refuse_grid(scene, samples)
            self.dimensions = Dimensions.of(scene)
            self.pixel_samples = PixelSamples(scene.sampling, self.dimensions.count)
            self.sample_count = scene.sampling.samples_per_pixel
            # see the module page
            skip_hidden = skip_hidden and scene.camera.aperture == 0 and not scene.moving
        self.skip_hidden = skip_hidden
        self.dtype = dtype
        self.progress = progress  # told each finished tile's pixel count
        self.hits = hits  # False: no pixel's centre hit kept, and no ray cast for it
        self.arrays = SceneArrays.of(self.scene)
        shaded = needs_shading(self.scene)
        self.secondary = secondary_caster(self.scene, cast, self.arrays) if shaded else None

    def regions(self) -> Iterator[Region]:
        band = RAYS_PER_BAND
        if self.scene.blurred:  # the band's times, pixels x samples (the module page)
            band = min(band, TIMES_PER_BAND // self.sample_count)
        return regions(self.scene, self.skip_hidden, self.arrays, band)

    def batches(self) -> Iterator[Batch]:
        """Every region's pixels at every sample offset, in the order their colours are summed."""
        if self.pixel_samples is not None:
            yield from self._distributed_batches()
            return
        offsets = self.offsets
        centre = centre_sample(self.samples) if self.hits else -1  # -1: no sample's hits kept
        for region in self.regions():
            pixels = len(region.rows) * len(region.cols)
            for k, (a, b) in enumerate(offsets):
                x, y = region_points(region.rows, region.cols, a, b)
                last = k == len(offsets) - 1 and centre is not None
                yield Batch(region, x, y, (a, b), centre=k == centre, finishes=pixels * last)
            if centre is None:  # even n: no sample sits at the centre, so cast one there
                x, y = region_points(region.rows, region.cols)
                yield Batch(region, x, y, (0.5, 0.5), True, colour=False, finishes=pixels)

    def _distributed_batches(self) -> Iterator[Batch]:
        """A distributed render's batches: each region's pixels at sample k, for every k, each
        point in its pixel (and on the lens and lights, its glossy perturbations and its time)
        by the sample's uniform numbers; then the pixel centres, cast only for the hits the
        image keeps (at the shutter's opening, in a scene that moves), where it keeps them."""
        width = self.scene.camera.width
        shutter = self.scene.sampling.shutter
        for region in self.regions():
            rows = np.repeat(np.asarray(region.rows), len(region.cols))
            cols = np.tile(np.asarray(region.cols), len(region.rows))
            pixels = rows * width + cols
            times = self._times(pixels)  # (P, S), or None
            for k in range(self.sample_count):
                uniforms = self.pixel_samples.of(pixels, k)
                x, y = point_in_pixel(rows, cols, uniforms[:, 0:2])
                at = None if times is None else times[:, k]
                last = k == self.sample_count - 1 and not self.hits
                yield Batch(region, x, y, None, uniforms=uniforms, times=at,
                            finishes=len(pixels) * last)  # fmt: skip
            if not self.hits:
                continue
            x, y = region_points(region.rows, region.cols)
            at = None if times is None else np.full(len(pixels), float(shutter[0]))
            yield Batch(
                region, x, y, (0.5, 0.5), True, colour=False, finishes=len(pixels), times=at
            )

    def _times(self, pixels: np.ndarray) -> np.ndarray | None:
        """The times ``(P, S)`` of the S samples of pixels ``(P,)`` in a scene that moves (each
        its own with the shutter open a while, else all at its opening); None: nothing moves."""
        if not self.scene.moving:
            return None
        shutter_open, shutter_close = self.scene.sampling.shutter
        if not self.scene.blurred:
            return np.full((len(pixels), self.sample_count), float(shutter_open))
        uniforms = self.pixel_samples.stratum(pixels, self.dimensions.time)
        return shutter_times(shutter_open, shutter_close, uniforms)

    def viewing_rays(self, batch: Batch) -> ViewingRays:
        """The rays through the batch's points that some object's screen rectangle holds; a
        point no rectangle holds gets no ray (it sees the background). A distributed sample's
        rays with a lens start on it (:func:`raykit.camera.thin_lens_rays`)."""
        seen, pairs = _seen_and_pairs(batch.region, batch.x, batch.y, batch.grid)
        x, y = (batch.x, batch.y) if seen is None else (batch.x[seen], batch.y[seen])
        uniforms, times = batch.uniforms, batch.times
        if uniforms is not None and seen is not None:
            uniforms = uniforms[seen]
        if times is not None and seen is not None:
            times = times[seen]
        camera = self.scene.camera
        if uniforms is not None and camera.aperture > 0:
            lens = self.dimensions.lens
            origins, directions = thin_lens_rays(camera, x, y, uniforms[:, lens : lens + 2])
        else:
            origins, directions = rays_through(camera, x, y)
        return ViewingRays(
            origins.astype(self.dtype, copy=False),
            directions.astype(self.dtype, copy=False),
            seen,
            pairs,
            uniforms,
            times,
        )

    def on_lights(self, rays: ViewingRays) -> np.ndarray | None:
        """The rays' uniform numbers for the area lights ``(M, max_depth + 1, A, 2)``, as
        :func:`raykit.shading.shade` takes them; None outside a distributed sample."""
        if rays.uniforms is None or not self.scene.area_lights:
            return None
        first = self.dimensions.light(0, 0)
        last = self.dimensions.light(self.scene.max_depth + 1, 0)
        shape = (len(rays.uniforms), self.scene.max_depth + 1, self.scene.area_lights, 2)
        return rays.uniforms[:, first:last].reshape(shape)

    def on_glossy(self, rays: ViewingRays) -> np.ndarray | None:
        """The rays' uniform numbers for the glossy perturbation of each mirror bounce
        ``(M, max_depth, 2)``, as :func:`raykit.shading.shade` takes them; None outside a
        distributed sample of a scene with a glossy mirror."""
        if rays.uniforms is None or not self.dimensions.glossy:
            return None
        first = self.dimensions.gloss(0)
        last = self.dimensions.gloss(self.scene.max_depth)
        shape = (len(rays.uniforms), self.scene.max_depth, 2)
        return rays.uniforms[:, first:last].reshape(shape)

    def nearest_hits(self, batch: Batch, rays: ViewingRays) -> Hits:
        """The nearest hits of the viewing rays, with the scene's object indices."""
        if not len(rays.origins):
            return Hits.none(0, self.scene.background)
        if rays.times is not None:  # a scene that moves: every object, at each ray's time
            return self.cast(self.scene, rays.origins, rays.directions, times=rays.times)
        return cast_region(
            self.cast, batch.region, self.arrays, rays.origins, rays.directions, rays.pairs
        )

    def colors_at(self, region: Region, x: np.ndarray, y: np.ndarray, illumination) -> np.ndarray:
        """Colours ``(N, 3)`` of the rays through scattered image points (x, y) ``(N,)`` of a
        region, as :func:`raykit.render.render` colours them (for adaptive sampling), with its
        ``illumination(plan, rays, hits)``."""
        batch = Batch(region, x, y, None)
        rays = self.viewing_rays(batch)
        hits = self.nearest_hits(batch, rays)
        colors = illumination(self, rays, hits)
        return _scatter(self.scene, rays.seen, len(x), hits, colors)[1]


@dataclass(frozen=True)
class ViewingRays:
    """Rays ``origins``, ``directions`` ``(M, 3)`` through the ``seen (N,)`` points of a batch
    (None: all N), in a crowded region the (object, ray) ``pairs`` to intersect, and in a
    distributed render the rays' uniform numbers and, in a scene that moves, their times."""

    origins: np.ndarray
    directions: np.ndarray
    seen: np.ndarray | None
    pairs: tuple[np.ndarray, np.ndarray] | None
    uniforms: np.ndarray | None = None  # a distributed sample's numbers, (M, dimensions)
    times: np.ndarray | None = None  # the rays' times (M,) in a scene that moves


def _scatter(scene: Scene, seen, count: int, hits: Hits, colors: np.ndarray):
    """The hits and colours of a batch's seen rays spread over all its ``count`` points: the
    points without a ray see the background."""
    if seen is None:
        return hits, colors
    every = Hits.none(count, scene.background)
    all_colors = every.color.copy()
    every.index[seen], every.t[seen], every.color[seen] = hits.index, hits.t, hits.color
    all_colors[seen] = colors
    return every, all_colors


class Image:
    """The image being rendered: colours summed over samples, and per pixel the centre ray's
    object index and t (see :class:`raykit.render.Render`)."""

    def __init__(self, plan: Plan) -> None:
        camera = plan.scene.camera
        self.plan = plan
        self.rgb = np.zeros((camera.height, camera.width, 3))
        shape = (camera.height, camera.width)
        self.object_index = np.empty(shape, dtype=np.int64) if plan.hits else None
        self.t = np.empty(shape) if plan.hits else None

    def store(self, batch: Batch, rays: ViewingRays, hits: Hits, colors: np.ndarray) -> None:
        """Add the batch's colours to its pixels' sums; keep a centre batch's hits."""
        region = batch.region
        hits, colors = _scatter(self.plan.scene, rays.seen, len(batch.x), hits, colors)
        shape = (len(region.rows), len(region.cols))
        if batch.colour:
            self.rgb[region.pixels] += colors.reshape(*shape, 3)
        if batch.centre:
            self.object_index[region.pixels] = hits.index.reshape(shape)
            self.t[region.pixels] = hits.t.reshape(shape)
        if batch.finishes and self.plan.progress is not None:
            self.plan.progress(batch.finishes)

    def mean(self) -> np.ndarray:
        return self.rgb / self.plan.sample_count


def cast_region(
    cast: SceneCaster,
    region: Region,
    arrays: SceneArrays,
    origins: np.ndarray,
    directions: np.ndarray,
    pairs: tuple[np.ndarray, np.ndarray] | None = None,
) -> Hits:
    """The nearest hits of a region's rays ``(N, 3)``, with the scene's object indices:
    ``cast`` over the region's objects or, given ``pairs`` (region object, ray) ``(P,)`` each,
    only those pairs, all at once (:mod:`raykit.engine.pairs`): the same hits if the pairs hold
    every object each ray can hit."""
    if pairs is None:
        hits = cast(region.scene, origins, directions)
        hits.index = region.index_of[hits.index]
        return hits
    which, ray = pairs
    index, t, color = nearest_of_pairs(
        region.whole, arrays, origins, directions, ray, region.index_of[which]
    )
    hits = Hits.none(len(origins), region.whole.background)
    found = index >= 0
    hits.index[found], hits.t[found], hits.color[found] = index[found], t[found], color[found]
    return hits


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

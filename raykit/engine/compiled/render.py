"""Repeats :mod:`raykit.render`: the lecture's loop over pixels (:func:`render`, of a scene made
ready once by :func:`prepare`) and :func:`raykit.render.cast` for any rays (:func:`cast_rays`,
:func:`caster`). The loop runs as jobs that workers take in turn (:mod:`.jobs`, on the threads of
:mod:`.pool`), each worker a call of one entry point: :func:`trace_flat` for a flat scene and
:func:`trace_lit` for a shaded one (two, so that a flat scene never compiles shading; and a
shaded scene compiles mirror rays only if it has mirrors, :func:`_entry`), :func:`trace_sampled`
for a distributed scene and :func:`trace_moving` for one whose spheres move."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, prange
from numba.extending import register_jitable

from raykit.camera import centre_sample, sample_offsets
from raykit.engine.adaptive import edge_pixels, refine
from raykit.engine.choice import entry_point, refuse_distributed
from raykit.engine.compiled.billboards import billboard_color_at, hit_billboard
from raykit.engine.compiled.bvh import DIRECT_HITS, nearest_hit, new_stack
from raykit.engine.compiled.camera import (
    CameraNumbers,
    camera_tuple,
    lens_tuple,
    rays_through,
    thin_lens_rays,
)
from raykit.engine.compiled.compiling import JOB, KERNEL, MAKES_ARRAYS, ONE_RAY, keep_freed_memory
from raykit.engine.compiled.jobs import (
    CHUNK,
    Film,
    background_job,
    centre_rays,
    flat_rooms,
    grain_taken,
    job_of,
    job_pixel,
    job_points,
    keeps_hits,
    lit_rooms,
    moving_rooms,
    pixel_means,
    sampled_rooms,
)
from raykit.engine.compiled.noise import (
    SOBOL,
    Noise,
    pixel_keys,
    sample_numbers,
    scene_noise,
    sobol_numbers,
)
from raykit.engine.compiled.pool import each_at_once, run, shares
from raykit.engine.compiled.sampling import point_in_pixel, shutter_times
from raykit.engine.compiled.scene import (
    _NO_TREE,
    Arrays,
    CompiledScene,
    Motion,
    Shading,
    Tree,
    every_object_tree,
    scene_arrays,
    scene_motion,
    scene_shading,
    scene_tree,
)
from raykit.engine.compiled.shading import (
    bounce_on,
    light_lanes,
    mirror_rays,
    shade,
    surface_lanes,
)
from raykit.engine.compiled.shadows import SHADOW_CANDIDATES, shadow_lists
from raykit.engine.compiled.spheres import center_at, hit_sphere
from raykit.engine.compiled.tiles import (
    Tiles,
    primary_ray,
    primary_rays,
    row_objects,
    screen_tiles,
)
from raykit.engine.regions import refuse_grid
from raykit.engine.tiles import regions
from raykit.hits import Hits
from raykit.scene import Scene
from raykit.surfaces import OFFSET_FACTOR

keep_freed_memory()  # each render's outputs reuse the last one's pages, where glibc allows
ROWS_PER_CALL = 32  # rows of pixels per kernel call when a progress bar is to move
SAMPLED_PIXELS = 64  # pixels per job of a distributed render at least, each with all its samples
SAMPLED_LANES = 256  # samples shaded together (sampled_lanes): of one pixel, or whole pixels
SAMPLED_SIDE = 16  # the side of a pinhole's distributed render's screen tiles (row_objects)


@register_jitable
def job_pixels(count: int) -> int:
    """The pixels of each job of a distributed render of ``count`` samples a pixel, for the
    caller that lays the jobs out and the kernels that take them (plain Python in one, compiled
    into the other): SAMPLED_PIXELS, or as many as fill SAMPLED_LANES lanes where a pixel's
    samples are fewer than SAMPLED_LANES // SAMPLED_PIXELS (:func:`sampled_lanes` batches no
    more than a job, and a batch of too few lanes pays its kernels' calls for too few)."""
    return max(SAMPLED_PIXELS, SAMPLED_LANES // count)


class Prepared(NamedTuple):
    """A scene made ready for the kernels (:func:`prepare`): its :class:`Arrays`, screen tiles
    (:func:`screen_tiles`; none for a distributed scene through a lens or with moving spheres, whose
    rays they do not bound), BVH (:class:`Tree`, for shadow and mirror rays, and a distributed
    render's viewing rays where no short list of objects serves them, :func:`cast_batch`; empty
    when the scene has none), :class:`Shading` (lights and materials) and
    camera (:func:`camera_tuple`); and a distributed scene's thin lens (:func:`lens_tuple`) and
    :class:`Noise` (None for another scene), and its :class:`Motion` (nothing moving but in a scene
    with a shutter; such a scene's tree is :func:`every_object_tree`); and the ``entry`` point that
    renders it (:func:`raykit.engine.choice.entry_point`, which asks every object's material: asked
    once here, not at each render)."""

    scene: Scene
    arrays: Arrays
    tiles: Tiles
    tree: Tree
    shading: Shading
    camera: CameraNumbers
    lens: tuple
    noise: Noise | None
    motion: Motion
    entry: str


def prepare(scene: Scene) -> Prepared:
    """Everything the kernels need of ``scene`` that does not depend on the samples: made once,
    it can be rendered many times (:func:`render`). It is what Mitsuba's ``load_dict`` does when
    it builds its BVH, and the camera's screen tiles besides (a raykit scene holds its camera).
    Refuses, in one line, what no kernel renders yet
    (:func:`raykit.engine.choice.refuse_distributed`). The textures' texels are got first:
    those the cache of decoded textures holds, and the small ones, on this thread; the large
    ones it lacks decode on as many threads as a render takes
    (:func:`~raykit.engine.compiled.pool.each_at_once`). Only a large decode lets go of Python's
    lock for long (Pillow inflates a PNG without it): other threads would only slow the rest,
    which is Python's work."""
    refuse_distributed(scene)
    textures = list(dict.fromkeys(b.texture for b in scene.billboards if b.texture is not None))
    undecoded = [texture for texture in textures if _long_to_decode(texture)]
    each_at_once(_texels, undecoded, numba.get_num_threads())
    arrays = scene_arrays(scene)
    shading = scene_shading(scene)
    tree = scene_tree(scene) if shading.shaded or scene.distributed else _NO_TREE
    if scene.moving:  # no box of the spheres as they stand bounds them: every object
        tree = every_object_tree(scene)
    noise = scene_noise(scene) if scene.distributed else None
    if not scene.distributed:
        tiles = screen_tiles(scene, arrays)
    elif lens_tuple(scene)[0] > 0 or scene.moving:  # a lens's rays do not start at the eye,
        tiles = _NO_TILES  # and a moving sphere has no one rectangle: no screen tile bounds them
    else:  # a pinhole's: each sample's ray goes through a point of its own pixel (row_objects)
        tiles = screen_tiles(scene, arrays, size=SAMPLED_SIDE, packets=False)
    return Prepared(scene, arrays, tiles, tree, shading, camera_tuple(scene), lens_tuple(scene),
                    noise, scene_motion(scene), entry_point(scene))  # fmt: skip


def _long_to_decode(texture) -> bool:
    """Whether getting ``texture``'s texels is a long decode: a large texture file that the
    cache lacks (:meth:`raykit.io.textures.Texture.in_cache`, which reads it if it has it).
    Texels given as an array (:class:`raykit.billboards.Texels`) are at hand."""
    in_cache = getattr(texture, "in_cache", None)
    return in_cache is not None and texture.large and not in_cache()


def _texels(texture) -> None:
    """A texture's texels, got (decoded, and kept by it)."""
    texture.rgba  # noqa: B018


_NO_TILES = Tiles(np.zeros(1, np.int64), np.zeros(0, np.int64), np.zeros((0, 5)), 1, 1, False)


def render(
    scene: Scene | Prepared,
    samples: int = 1,
    *,
    adaptive: bool = False,
    progress=None,
    hits: bool = True,
):
    """What :func:`raykit.render.render` renders, with the kernels above:
    ``(rgb (H, W, 3), object_index (H, W), t (H, W))``, of a scene or of a :class:`Prepared`
    one; with ``hits`` False, ``(rgb, None, None)``, and no ray is cast for the two
    (:func:`~.jobs.keeps_hits`). ``progress`` is told each band of finished pixels, as the numpy
    engine tells it each tile. A distributed scene takes its own samples (:func:`trace_sampled`)."""
    offsets = sample_offsets(samples)  # refuses n < 1 before any work
    n = 1 if adaptive else samples  # adaptive: one ray per pixel first, as the numpy engine
    if n != samples:
        offsets = sample_offsets(n)
    refuse_grid(scene.scene if isinstance(scene, Prepared) else scene, samples)
    prepared = scene if isinstance(scene, Prepared) else prepare(scene)
    if prepared.noise is not None:
        return _render_sampled(prepared, progress, hits)
    scene, arrays, tiles = prepared.scene, prepared.arrays, prepared.tiles
    name, trace, kernels = _entry(prepared)
    width, height = scene.camera.width, scene.camera.height
    centre = centre_sample(n)
    empty = _mean_of_samples(arrays.background, len(offsets))
    rgb = np.empty((height * width, 3))  # first written by the workers: faster than by numpy
    refined = adaptive and samples > 1
    kept = height * width if hits or refined else 0  # the refinement finds edges by index
    index = np.empty(kept, dtype=np.int64)
    t = np.empty(kept)
    tiles_x, size = tiles.tiles_x, tiles.size
    tile_count = -(-height // size) * tiles_x
    # tiles per kernel call: bands of rows for a progress bar, else all at once (each call
    # starts every worker anew, and waits for the slowest)
    band = max(1, ROWS_PER_CALL // size) * tiles_x if progress is not None else tile_count
    nothing = np.zeros(0)
    film = Film(width, height, nothing, nothing, offsets, -1 if centre is None else centre, rgb,
                index, t)  # fmt: skip
    for first in range(0, tile_count, band):
        run(
            name,
            trace,
            *kernels,
            film,
            empty,
            shares(np.arange(first, min(first + band, tile_count))),
            rooms=_rooms(prepared, film),
        )
        if progress is not None:
            rows = min(height, (first + band) // tiles_x * size) - first // tiles_x * size
            progress(rows * width)
    rgb, index, t = (
        rgb.reshape(height, width, 3),
        index.reshape(height, width) if kept else None,
        t.reshape(height, width) if kept else None,
    )
    if refined:  # the numpy engine's refinement, with these colours
        edge = edge_pixels(rgb, index)
        at_the_point = np.zeros((1, 2))  # each point its own one sample

        def colors(region, x, y):
            x, y = np.asarray(x, float), np.asarray(y, float)
            out = np.empty((len(x), 3))
            points = Film(width, height, x, y, at_the_point, 0, out, np.empty(len(x), np.int64),
                          np.empty(len(x)))  # fmt: skip
            run(name, trace, *kernels, points, empty, shares(np.arange(-(-len(x) // CHUNK))),
                rooms=_rooms(prepared, points))  # fmt: skip
            return out

        refine(regions(scene, skip_hidden=False), colors, rgb, edge, samples)
    return (rgb, index, t) if hits else (rgb, None, None)


def _render_sampled(prepared: Prepared, progress=None, hits: bool = True):
    """:func:`render` of a distributed scene, prepared (:func:`trace_sampled`): in one call,
    or in bands of ROWS_PER_CALL rows for a progress bar; its pixels' hits where ``hits``."""
    name, trace, kernels = _entry(prepared)
    width, height = prepared.scene.camera.width, prepared.scene.camera.height
    pixels = width * height
    rgb = np.empty((pixels, 3))
    index = np.empty(pixels if hits else 0, dtype=np.int64)
    t = np.empty(pixels if hits else 0)
    job = job_pixels(prepared.noise.count)
    starts = np.arange(0, pixels, job)
    band = -(-ROWS_PER_CALL * width // job) if progress is not None else len(starts)
    nothing = np.zeros(0)  # no image points, no sample offsets: each pixel takes its own samples
    film = Film(width, height, nothing, nothing, np.zeros((0, 2)), -1, rgb, index, t)
    for first in range(0, len(starts), band):
        jobs = starts[first : first + band]
        run(name, trace, *kernels, film, shares(jobs), rooms=_rooms(prepared, film))
        if progress is not None:
            progress(min(pixels, jobs[-1] + job) - jobs[0])
    if not hits:
        return rgb.reshape(height, width, 3), None, None
    return rgb.reshape(height, width, 3), index.reshape(height, width), t.reshape(height, width)


def _mean_of_samples(color: np.ndarray, count: int) -> np.ndarray:
    """``color (3,)`` summed ``count`` times and divided by it, as :func:`pixel_means` takes the
    mean of a pixel's samples (the result may differ from ``color`` in its last bit)."""
    total = np.zeros(3)
    for _ in range(count):
        total = total + color
    return total / count


def _rooms(prepared: Prepared, film: Film) -> Callable[[], tuple]:
    """What makes each worker's rooms (:mod:`~raykit.engine.compiled.jobs`) for a call of the
    entry point of ``prepared`` (:func:`_entry`) into ``film``: its last arguments. A tile's rays
    or a CHUNK of image points, each with its samples and the ray through its centre; a
    distributed render's SAMPLED_LANES samples, of as many pixels as a job's."""
    noise = prepared.noise
    if noise is not None:
        if prepared.entry == "trace_moving":
            return functools.partial(moving_rooms, prepared.arrays, noise)
        pixels = min(SAMPLED_LANES, job_pixels(noise.count))
        return functools.partial(sampled_rooms, SAMPLED_LANES, pixels, prepared.shading, noise)
    size = prepared.tiles.size
    n = (CHUNK if len(film.xs) else size * size) * (len(film.offsets) + 1)
    if prepared.entry == "trace_flat":
        return functools.partial(flat_rooms, n)
    return functools.partial(lit_rooms, n, prepared.shading)


def _entry(prepared: Prepared) -> tuple:
    """``(name, entry point, its leading arguments)`` for a prepared scene, the name
    :func:`raykit.engine.choice.entry_point` gave it (``prepared.entry``): :func:`trace_flat` for a
    flat scene, which compiles no shading, else :func:`trace_lit` with the tree and :class:`Shading`
    (in a :class:`CompiledScene`), and ``bounces``: True for ``trace_mirrors`` (a ray may bounce off
    a mirror), else None, a type of its own to numba, for which :func:`lit_job` compiles no mirror
    code. The two are compiled apart, and named apart for the cache's markers and the progress line.
    A distributed scene's: :func:`trace_moving` for one whose spheres move, else
    :func:`trace_sampled` with ``bounces`` as above (``trace_sampled_mirrors``, or
    ``trace_sampled``)."""
    name = prepared.entry
    scene = CompiledScene(prepared.arrays, prepared.tree, prepared.shading)
    distributed = (scene, prepared.camera, prepared.lens, prepared.noise)
    if name == "trace_moving":
        return name, trace_moving, (*distributed, prepared.motion)
    if name in ("trace_sampled", "trace_sampled_mirrors"):
        bounces = True if name == "trace_sampled_mirrors" else None
        return name, trace_sampled, (*distributed, prepared.tiles, bounces)
    if name == "trace_flat":
        return name, trace_flat, (prepared.arrays, prepared.tiles, prepared.camera)
    bounces = True if name == "trace_mirrors" else None
    return name, trace_lit, (scene, prepared.tiles, prepared.camera, bounces)


@njit(**KERNEL)
def trace_flat(arrays, tiles, camera, film, empty, work, room, grain):
    """The lecture's loop for a flat scene, into ``film`` (:class:`~.jobs.Film`): for each pixel,
    per sample offset ``offsets (S, 2)`` in order, the viewing ray and its nearest hit
    (:func:`primary_ray`, or a packet of them: :func:`primary_rays`) and its flat colour, summed and
    divided by S as :class:`raykit.engine.regions.Image` takes the mean; and the object index and t
    of the ray through the pixel centre, which is sample ``centre`` (-1: cast one more ray there),
    where the film keeps them (:func:`~.jobs.keeps_hits`).
    Results go to ``rgb (P, 3)``, ``index``, ``t (P,)``. Which pixels, either way:

    * whole tiles (``xs`` empty): ``work.jobs (J,)`` are tile numbers (:func:`screen_tiles`),
      and their pixels are the image's, row by row (P = ``height`` x ``width``) with their
      upper-left corners at (column, row). A tile that no object's screen rectangle meets sees
      only the background: its pixels are given ``empty (3,)`` (the background's mean over the
      samples, :func:`_mean_of_samples`), index -1 and t = inf, and no ray;
    * points (``xs``, ``ys (P,)``, the upper-left corners): ``work.jobs`` are CHUNKs of them.

    A call is one worker (:func:`~.pool.run_workers` makes one a thread, each with the same
    arguments but its rooms): with its own ``room`` for a job's rays (making it for each job cost
    more than a small tile's rays) and ``grain`` (:func:`~.jobs.flat_rooms`), it takes the jobs of
    ``work`` a grain at a time (:func:`~.jobs.grain_taken`). Each job runs on one core, whole
    (:func:`flat_job`, copied into it: :data:`~raykit.engine.compiled.compiling.JOB`). An entry
    point makes no array: its rooms are made before its call, so that it counts no references."""
    points = len(film.xs)
    while grain_taken(work, grain):
        for j in range(grain[0], grain[1]):
            job = job_of(work, j, tiles, film)
            if points or tiles.start[job.tile] < tiles.start[job.tile + 1]:
                flat_job(arrays, tiles, camera, film, job, room)
            else:
                background_job(film, job, empty)


@njit(**JOB)
def flat_job(arrays, tiles, camera, film, job, room):
    """One job of :func:`trace_flat` (a :class:`TileJob`) into ``film`` (:class:`Film`): its
    pixels (:func:`job_pixel`), all in its tile (-1: points, each in its own), with the
    worker's ``room`` (:func:`new_ray_room`). One ray at a time, each colour goes straight into
    its pixel's sum and no ray is kept; in packets, the rays are traced together
    (:func:`primary_rays`), then summed."""
    offsets, rgb, index, t, centre = film.offsets, film.rgb, film.index, film.t, film.centre
    samples = len(offsets)
    tile = job.tile
    hits, extra = keeps_hits(film), centre_rays(film)
    if tile < 0 or not tiles.packets:
        for down in range(job.rows):
            for along in range(job.across):
                p, px, py = job_pixel(film, job, down, along)
                r_sum, g_sum, b_sum = 0.0, 0.0, 0.0
                for sample in range(samples):
                    x, y = px + offsets[sample, 0], py + offsets[sample, 1]
                    hit = primary_ray(arrays, tiles, camera, x, y, tile, room.holding).nearest
                    if sample == centre and hits:
                        index[p], t[p] = hit.index, hit.t
                    r_sum += hit.r
                    g_sum += hit.g
                    b_sum += hit.b
                rgb[p, 0] = r_sum / samples
                rgb[p, 1] = g_sum / samples
                rgb[p, 2] = b_sum / samples
                if extra:
                    hit = primary_ray(arrays, tiles, camera, px + 0.5, py + 0.5, tile, room.holding)
                    index[p], t[p] = hit.nearest.index, hit.nearest.t
        return
    job_points(film, job, room.xy)
    primary_rays(arrays, tiles, camera, job, len(offsets), extra, room)
    pixel_means(film, job, room.colors, room.best, room.best_t)


@njit(**KERNEL)
def trace_lit(scene, tiles, camera, bounces, film, empty, work, room, shading_room, grain):
    """:func:`trace_flat` for a shaded ``scene`` (:func:`raykit.shading.needs_shading`; a
    :class:`CompiledScene`, with its BVH and its :class:`Shading`): each job's pixels
    (:func:`lit_job`) take the colour :func:`raykit.shading.shade` gives them. A call is one
    worker, as there, with its rooms (:func:`~.jobs.lit_rooms`)."""
    points = len(film.xs)
    while grain_taken(work, grain):
        for j in range(grain[0], grain[1]):
            job = job_of(work, j, tiles, film)
            if points or tiles.start[job.tile] < tiles.start[job.tile + 1]:
                lit_job(scene, tiles, camera, bounces, film, job, room, shading_room)
            else:
                background_job(film, job, empty)


@njit(**JOB)
def lit_job(scene, tiles, camera, bounces, film, job, room, shading_room):
    """One job of :func:`trace_lit` (a :class:`TileJob`), with the worker's ``room``
    (:class:`RayRoom`) and ``shading_room`` (:class:`ShadingRoom`): all its viewing rays' hits
    first, then each light's :func:`shadow_lists` for the box their surface points lie in, each
    light for all the points at once (:func:`surface_lanes`, :func:`light_lanes`), then, in a
    scene with mirrors (``bounces`` True, not None: see :func:`_entry`), their rays
    (:func:`mirror_rays`), and the pixels' means (:func:`pixel_means`) into ``film``
    (:class:`Film`). ``bounces`` is an argument of its own, not a field of a tuple: numba drops
    the branch it decides only for an argument's type."""
    arrays, tree, shading = scene
    tile = job.tile
    xy, rays, best, best_t, colors = room.xy, room.rays, room.best, room.best_t, room.colors
    made, holding = room.made, room.holding
    stack, box, volume, lanes = (
        shading_room.stack, shading_room.box, shading_room.volume, shading_room.lanes
    )  # fmt: skip
    candidates, counts = shading_room.candidates, shading_room.counts
    n = job_points(film, job, xy)
    if tile >= 0 and tiles.packets:
        primary_rays(arrays, tiles, camera, job, len(film.offsets), centre_rays(film), room)
    else:
        for i in range(n):
            viewing = primary_ray(arrays, tiles, camera, xy[0, i], xy[1, i], tile, holding)
            hit, ray = viewing.nearest, viewing.ray
            made[i], best[i], best_t[i] = viewing.made, hit.index, hit.t
            colors[0, i], colors[1, i], colors[2, i] = hit.r, hit.g, hit.b
            rays[0, i], rays[1, i], rays[2, i] = ray.o0, ray.o1, ray.o2
            rays[3, i], rays[4, i], rays[5, i] = ray.d0, ray.d1, ray.d2
    shaded = job.rows * job.across * len(film.offsets)
    largest = surface_lanes(arrays, shading, rays, best, best_t, colors, shaded, lanes, box)
    if shading.shadows:
        # shadow rays start off the surface by OFFSET_FACTOR x error x |n|, and |n| < 2 but
        # for a sphere smaller than its own rounding
        pad = 2.0 * OFFSET_FACTOR * largest
        shadow_lists(arrays, tree, shading, stack, box, pad, volume, candidates, counts)
    if shading.lit:
        light_lanes(scene, stack, rays, best, shaded, lanes, candidates, counts, xy[:0])
    total = lanes.total
    for i in range(shaded):  # as shade weighs them: 1 x the colour, added to nothing
        if not made[i]:
            continue
        if best[i] < 0:  # the background
            c0, c1, c2 = colors[0, i], colors[1, i], colors[2, i]
        else:
            c0, c1, c2 = total[0, i], total[1, i], total[2, i]
        colors[0, i], colors[1, i], colors[2, i] = 0.0 + 1.0 * c0, 0.0 + 1.0 * c1, 0.0 + 1.0 * c2
    if bounces is not None:  # None in a scene with no mirror: this branch is not compiled
        mirror_rays(scene, stack, lanes, rays, best, made, shaded, colors)
    pixel_means(film, job, colors, best, best_t)


@njit(**KERNEL)
def trace_sampled(scene, camera, lens, noise, tiles, bounces, film, work, room, shading_room,
                  sample_room, grain):  # fmt: skip
    """The lecture's loop for a distributed scene (stage 5, as :class:`raykit.engine.regions.Plan`
    batches it) whose spheres stand still: for each pixel, each of its ``noise.count`` samples in
    order, from the sample's uniform numbers (:func:`~raykit.engine.compiled.noise.sample_numbers`),
    a point in the pixel, a ray through the pinhole or from the lens (``lens``: :func:`lens_tuple`),
    its nearest hit, and its colour, flat or shaded (its points on the area lights and its glossy
    perturbations from the same numbers), summed and divided by the count as
    :class:`raykit.engine.regions.Image` takes the mean; and the object index and t of the pinhole
    ray through the pixel centre, where the film keeps them (:func:`~.jobs.keeps_hits`).
    ``work.jobs (J,)``: the first pixel of each job of :func:`job_pixels` (row-major, P =
    ``len(film.rgb)``); results into ``film`` (:class:`~.jobs.Film`: ``rgb (P, 3)``,
    ``index``, ``t (P,)``). Through a pinhole, each batch of a job's samples tests only the objects
    its pixels' screen ``tiles`` list (:func:`~.tiles.row_objects`); a lens's rays do not start at
    the eye, and no tile bounds them (``tiles`` is empty: as the reference, each tests every
    object). The answer is :func:`raykit.render.cast`'s either way. A job's samples go in lanes
    (:func:`sampled_lanes`); ``bounces``, True in a scene with mirrors, else None (a type of its own
    to numba, for which no mirror ray is compiled), as :func:`trace_lit` takes it. A scene whose
    spheres move renders by :func:`trace_moving`, compiled apart, so that a still scene never
    compiles its kernels. A call is one worker, taking grains of jobs as :func:`trace_flat`'s does;
    a pixel's numbers depend on it alone, so the image does not depend on which takes which. Its
    rooms (:func:`~.jobs.sampled_rooms`), each worker's own, are made before its call, as every
    entry point's are, and its one job, :func:`sampled_lanes`, is copied into it
    (:data:`~raykit.engine.compiled.compiling.JOB`)."""
    every_object(scene.tree, scene.shading, shading_room)
    while grain_taken(work, grain):
        for j in range(grain[0], grain[1]):
            sampled_lanes(scene, camera, lens, noise, tiles, bounces, film, work.jobs[j],
                          sample_room, room, shading_room)  # fmt: skip


@njit(**KERNEL)
def trace_moving(scene, camera, lens, noise, motion, film, work, stack, sample_room, centers,
                 grain):  # fmt: skip
    """:func:`trace_sampled` for a scene whose spheres move (``motion``: :class:`Motion`): each
    sample's ray has its own time (:func:`shutter_times`), and its viewing, shadow and mirror
    rays and its normals see the moving spheres there (:func:`center_at`): each worker keeps its
    own copy of the scene's arrays, their centres moved to the time of the ray it traces
    (:func:`spheres_at`), and the tree is :func:`every_object_tree`, as the reference tests
    every object then: its ``centers (S, 3)`` are the worker's own copy of the scene's
    (:func:`~.jobs.moving_rooms`). A job is one sample at a time (:func:`sampled_job`, copied
    into it as :func:`trace_sampled` copies its job)."""
    arrays = scene.arrays
    at_time = Arrays(centers, arrays.radii, arrays.sphere_colors,
                     arrays.corners, arrays.n, arrays.alpha_axes, arrays.beta_axes,
                     arrays.board_colors, arrays.texture_start, arrays.texture_width,
                     arrays.texture_height, arrays.texels, arrays.background)  # fmt: skip
    moved = CompiledScene(at_time, scene.tree, scene.shading)
    while grain_taken(work, grain):
        for j in range(grain[0], grain[1]):
            sampled_job(arrays.centers, moved, camera, lens, noise, motion, film, work.jobs[j],
                        stack, sample_room)  # fmt: skip


@njit(**KERNEL)
def spheres_at(standing, motion, centers, T):
    """The centres ``centers (S, 3)`` of the scene's spheres at one ray's time T, as
    :func:`raykit.render.cast` offers them: a sphere with a velocity at :func:`center_at` from
    where it stands at the shutter's opening, ``standing (S, 3)``, the others there."""
    for i in range(len(centers)):
        if motion.moves[i]:
            velocity = motion.velocities
            centers[i, 0], centers[i, 1], centers[i, 2] = center_at(
                standing[i, 0], standing[i, 1], standing[i, 2],
                velocity[i, 0], velocity[i, 1], velocity[i, 2], T,
            )  # fmt: skip


@njit(**JOB)
def sampled_job(standing, moved, camera, lens, noise, motion, film, first, stack, sample_room):
    """One job of :func:`trace_moving`: the :func:`job_pixels` pixels from pixel ``first`` into
    ``film``, with the worker's ``stack`` (:func:`new_stack`), room for a sample's uniform
    numbers and what its pixel's samples share (:class:`~.jobs.SampleRoom`), and the worker's
    copy of the scene, ``moved``, whose sphere centres it moves from where they stand,
    ``standing (S, 3)``, to each ray's time in a scene that moves (:class:`Motion`), and every ray
    reads. (Not the scene itself: each tuple a kernel takes is compiled into it whole, read or
    not.)"""
    count, wanted, reads = noise.count, noise.wanted, noise.reads
    at_time, tree = moved.arrays, moved.tree
    numbers, keys = sample_room.numbers[0], sample_room.keys[0]
    width, rgb, index, t = film.width, film.rgb, film.index, film.t
    hits = keeps_hits(film)
    for p in range(first, min(first + job_pixels(count), len(rgb))):
        row, col = p // width, p % width
        r_sum, g_sum, b_sum = 0.0, 0.0, 0.0
        pixel_keys(noise.sampler, noise.seed, p, noise.count, wanted, keys)
        for k in range(count):
            sample_numbers(noise.sampler, k, noise.n, noise.table, wanted, reads, keys, numbers)
            if motion.moving:  # the ray's time: its own, or the shutter's opening
                T = motion.shutter_open
                if motion.time >= 0:
                    T = shutter_times(motion.shutter_open, motion.shutter_close,
                                      numbers[motion.time])  # fmt: skip
                spheres_at(standing, motion, at_time.centers, T)
            x, y = point_in_pixel(row, col, numbers[noise.pixel], numbers[noise.pixel + 1])
            if lens[0] > 0:
                ray = thin_lens_rays(camera, lens, x, y, numbers[noise.lens],
                                     numbers[noise.lens + 1])  # fmt: skip
            else:
                ray = rays_through(camera, x, y)
            hit = nearest_hit(at_time, tree, stack, ray.o0, ray.o1, ray.o2, ray.d0, ray.d1,
                              ray.d2, np.inf)  # fmt: skip
            if moved.shading.shaded:
                c0, c1, c2 = shade(moved, stack, (ray.o0, ray.o1, ray.o2),
                                   (ray.d0, ray.d1, ray.d2), hit, numbers)  # fmt: skip
            else:  # no light: the object's flat colour
                c0, c1, c2 = hit.r, hit.g, hit.b
            r_sum += c0
            g_sum += c1
            b_sum += c2
        rgb[p, 0] = r_sum / count
        rgb[p, 1] = g_sum / count
        rgb[p, 2] = b_sum / count
        if not hits:
            continue
        ray = rays_through(camera, col + 0.5, row + 0.5)  # the pinhole's, with a lens
        if motion.moving:  # at the shutter's opening
            spheres_at(standing, motion, at_time.centers, motion.shutter_open)
        hit = nearest_hit(at_time, tree, stack, ray.o0, ray.o1, ray.o2, ray.d0, ray.d1, ray.d2,
                          np.inf)  # fmt: skip
        index[p], t[p] = hit.index, hit.t


@njit(**KERNEL)
def every_object(tree, shading, shading_room):
    """Each light's shadow list (:class:`ShadingRoom`) made every object of the scene, where
    they fit in one, for :func:`sampled_lanes`: its shadow rays start anywhere, so no box of
    them culls, and a list's answer is the tree's (any opaque hit before the light), each object
    tested for all the lanes at once. Else the lists stay empty (-1): the rays walk the tree."""
    objects = len(tree.order)
    if objects > SHADOW_CANDIDATES:
        return
    candidates, counts = shading_room.candidates, shading_room.counts
    for j in range(len(candidates)):
        for m in range(objects):
            candidates[j, m] = tree.order[m]
        counts[j] = objects


@njit(**KERNEL)
def cast_each(arrays, tree, stack, rays, count, best, best_t, colors):
    """:func:`nearest_hit` of each of ``count`` rays ``rays (6, N)`` (origins, then directions)
    through the tree, with a walk's ``stack``: the object index into ``best``, t into ``best_t``
    and the colour into ``colors (3, N)``. Called once for a batch of rays, its tree walk
    compiled once, not in each loop that casts them."""
    for i in range(count):
        hit = nearest_hit(arrays, tree, stack, rays[0, i], rays[1, i], rays[2, i], rays[3, i],
                          rays[4, i], rays[5, i], np.inf)  # fmt: skip
        best[i], best_t[i] = hit.index, hit.t
        colors[0, i], colors[1, i], colors[2, i] = hit.r, hit.g, hit.b


@njit(**ONE_RAY)
def cast_batch(arrays, tree, stack, near, nearby, rays, count, best, best_t, colors, t):
    """:func:`nearest_hit` for each of ``count`` rays ``rays (6, N)``, as :func:`cast_lanes` or
    :func:`cast_each` find it best: of the ``nearby`` objects ``near (K,)`` that can be hit
    (:func:`~.tiles.row_objects`; -1: every object may be), or of every object where a scene
    has DIRECT_HITS or fewer, each in lanes; else each ray through the tree."""
    if nearby >= 0:
        cast_lanes(arrays, near, nearby, rays, count, best, best_t, colors, t)
    elif len(tree.order) <= DIRECT_HITS:
        cast_lanes(arrays, tree.order, len(tree.order), rays, count, best, best_t, colors, t)
    else:
        cast_each(arrays, tree, stack, rays, count, best, best_t, colors)


@njit(**KERNEL)
def cast_lanes(arrays, order, objects, rays, count, best, best_t, colors, t):
    """:func:`nearest_hit` for each of ``count`` rays ``rays (6, N)`` (origins, then directions)
    among the first ``objects`` of ``order`` (DIRECT_HITS or fewer: every object of the scene,
    in the tree's order, or those the rays' pixels may show), each object in turn for all the
    rays, with :func:`keep_nearer`'s test for each ray, whose outcome does not depend on the
    order, so the same hits: the object index into ``best``, t into ``best_t`` and the colour
    into ``colors (3, N)``; ``t (N,)`` is room. The step that is the same for every ray (a
    sphere's t, a hit kept or not) is a loop the compiler turns into vector instructions."""
    background, spheres = arrays.background, len(arrays.radii)
    centers, radii, sphere_colors = arrays.centers, arrays.radii, arrays.sphere_colors
    for i in range(count):
        best[i], best_t[i] = -1, np.inf
        colors[0, i], colors[1, i], colors[2, i] = background[0], background[1], background[2]
    board_colors = arrays.board_colors
    for m in range(objects):
        obj = order[m]
        board = obj - spheres
        if obj < spheres:
            c0, c1, c2, R = centers[obj, 0], centers[obj, 1], centers[obj, 2], radii[obj]
            for i in range(count):
                t[i] = hit_sphere(rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i],
                                  rays[5, i], c0, c1, c2, R)  # fmt: skip
            r, g, b = sphere_colors[obj, 0], sphere_colors[obj, 1], sphere_colors[obj, 2]
        elif arrays.texture_start[board] < 0:  # one colour, opaque everywhere: as a sphere
            for i in range(count):
                t[i] = hit_billboard(rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i],
                                     rays[5, i], arrays, board)[0]  # fmt: skip
            r, g, b = board_colors[board, 0], board_colors[board, 1], board_colors[board, 2]
        else:  # a texture: the texel's colour and opacity where a hit is nearer
            for i in range(count):
                t_hit, alpha, beta = hit_billboard(rays[0, i], rays[1, i], rays[2, i],
                                                   rays[3, i], rays[4, i], rays[5, i], arrays,
                                                   board)  # fmt: skip
                if t_hit < best_t[i] or (t_hit == best_t[i] and t_hit < np.inf and obj < best[i]):
                    cr, cg, cb, opaque = billboard_color_at(arrays, board, alpha, beta)
                    if opaque:
                        best[i], best_t[i] = obj, t_hit
                        colors[0, i], colors[1, i], colors[2, i] = cr, cg, cb
            continue
        for i in range(count):  # keep_nearer's test, with & and | (no branch)
            nearer = (t[i] < best_t[i]) | ((t[i] == best_t[i]) & (t[i] < np.inf) & (obj < best[i]))
            best[i] = obj if nearer else best[i]
            best_t[i] = t[i] if nearer else best_t[i]
            colors[0, i] = r if nearer else colors[0, i]
            colors[1, i] = g if nearer else colors[1, i]
            colors[2, i] = b if nearer else colors[2, i]


@njit(**JOB)
def sampled_lanes(
    scene, camera, lens, noise, tiles, bounces, film, first, sample_room, room, shading_room
):
    """:func:`sampled_job` for a scene where nothing moves, its samples in lanes: SAMPLED_LANES
    samples at a time, of one pixel, or of as many whole pixels of one row as they hold (each batch
    calls kernels of its own, whose arguments cost as much as a few rays: a batch of one pixel's few
    samples paid them for too few), each sample with its row of ``sample_room.numbers
    (SAMPLED_LANES, D)``, the wanted ones copied into the columns of its ``columns (D,
    SAMPLED_LANES)`` (:class:`~.jobs.SampleRoom`); their viewing rays, their nearest hits
    (:func:`cast_lanes` of the objects their pixels' screen ``tiles`` list,
    :func:`~.tiles.row_objects`, where those are DIRECT_HITS or fewer, else of every object in a
    scene of DIRECT_HITS or fewer, else each ray through the tree), into ``room``
    (:class:`RayRoom`), then all of them shaded at once as :func:`lit_job` shades a tile's rays
    (:func:`surface_lanes`, :func:`light_lanes`, each area light at each ray's own point of it), the
    shadow rays against every object (:func:`every_object`); then each mirror's rays
    (:func:`bounce_on`, with the ray's row of numbers; only where ``bounces`` is True, not None:
    :func:`trace_sampled`), and the samples summed in order. A step the same for every sample is a
    loop the compiler turns into vector instructions, where one sample at a time waited on its
    divisions and branches. Each ray's operations are :func:`shade`'s, in its order, so the bits are
    :func:`sampled_job`'s."""
    arrays, tree, shading = scene
    count, wanted, reads = noise.count, noise.wanted, noise.reads
    numbers, columns, keys = sample_room.numbers, sample_room.columns, sample_room.keys
    near, tiled = sample_room.near, len(tiles.start) > 1
    width, rgb, index, t = film.width, film.rgb, film.index, film.t
    hits = keeps_hits(film)
    xy, rays, best, best_t, colors = room.xy, room.rays, room.best, room.best_t, room.colors
    lanes, box, stack = shading_room.lanes, shading_room.box, shading_room.stack
    total, point, normal, error = lanes.total, lanes.p, lanes.n, lanes.error
    per = max(1, SAMPLED_LANES // count)  # whole pixels a batch holds
    last = min(first + job_pixels(count), len(rgb))
    r_sum, g_sum, b_sum = 0.0, 0.0, 0.0
    p_first = first
    while p_first < last:  # batches of whole pixels, none across two rows (row_objects)
        pixels = min(per, last - p_first, width - p_first % width)
        nearby = row_objects(tiles, width, p_first, p_first + pixels - 1, near) if tiled else -1
        for k_first in range(0, count, SAMPLED_LANES):
            samples = min(SAMPLED_LANES, count - k_first)  # of each pixel in this batch
            shaded = pixels * samples
            for q in range(pixels):  # lane i = q·samples + j: sample k_first + j of pixel p
                pixel_keys(noise.sampler, noise.seed, p_first + q, count, wanted, keys[q])
            if noise.sampler == SOBOL:  # a dimension at a time, for the whole batch
                sobol_numbers(k_first, samples, pixels, noise.table, wanted, sample_room)
            else:
                for q in range(pixels):
                    for j in range(samples):
                        i = q * samples + j
                        u = numbers[i]
                        sample_numbers(noise.sampler, k_first + j, noise.n, noise.table, wanted,
                                       reads, keys[q], u)  # fmt: skip
                        for d in reads:
                            columns[d, i] = u[d]
            row = p_first // width  # of every pixel of the batch
            for q in range(pixels):
                col = p_first - row * width + q
                for j in range(samples):
                    i = q * samples + j
                    xy[0, i], xy[1, i] = point_in_pixel(row, col, columns[noise.pixel, i],
                                                        columns[noise.pixel + 1, i])  # fmt: skip
            if lens[0] > 0:  # a loop each, the same step for every lane
                for i in range(shaded):
                    ray = thin_lens_rays(camera, lens, xy[0, i], xy[1, i], columns[noise.lens, i],
                                         columns[noise.lens + 1, i])  # fmt: skip
                    rays[0, i], rays[1, i], rays[2, i] = ray.o0, ray.o1, ray.o2
                    rays[3, i], rays[4, i], rays[5, i] = ray.d0, ray.d1, ray.d2
            else:
                for i in range(shaded):
                    ray = rays_through(camera, xy[0, i], xy[1, i])
                    rays[0, i], rays[1, i], rays[2, i] = ray.o0, ray.o1, ray.o2
                    rays[3, i], rays[4, i], rays[5, i] = ray.d0, ray.d1, ray.d2
            cast_batch(arrays, tree, stack, near, nearby, rays, shaded, best, best_t, colors,
                       lanes.t)  # fmt: skip
            if shading.shaded:
                surface_lanes(arrays, shading, rays, best, best_t, colors, shaded, lanes, box)
                if shading.lit:
                    light_lanes(scene, stack, rays, best, shaded, lanes, shading_room.candidates,
                                shading_room.counts, columns)  # fmt: skip
            for q in range(pixels):  # each pixel's samples summed in order
                if k_first == 0:
                    r_sum, g_sum, b_sum = 0.0, 0.0, 0.0
                for j in range(samples):
                    i = q * samples + j
                    c0, c1, c2 = colors[0, i], colors[1, i], colors[2, i]
                    hit = best[i]
                    if shading.shaded:  # as shade weighs them: 1 x the colour, added to nothing
                        if hit >= 0:
                            c0, c1, c2 = total[0, i], total[1, i], total[2, i]
                        c0, c1, c2 = 0.0 + 1.0 * c0, 0.0 + 1.0 * c1, 0.0 + 1.0 * c2
                    if bounces is not None:  # None in a scene with no mirror: not compiled
                        if shading.shaded and hit >= 0:
                            c0, c1, c2 = bounce_on(
                                scene, stack, 0, hit, (point[0, i], point[1, i], point[2, i]),
                                (normal[0, i], normal[1, i], normal[2, i]),
                                (rays[3, i], rays[4, i], rays[5, i]), error[i], (c0, c1, c2),
                                (1.0, 1.0, 1.0), numbers[i],
                            )  # fmt: skip
                    r_sum += c0
                    g_sum += c1
                    b_sum += c2
                if k_first + samples == count:  # the pixel's last sample: its mean
                    p = p_first + q
                    rgb[p, 0] = r_sum / count
                    rgb[p, 1] = g_sum / count
                    rgb[p, 2] = b_sum / count
            if k_first + samples == count and hits:  # the batch's pixels done: their centres' hits
                for q in range(pixels):  # the pinhole's ray, with a lens too
                    p = p_first + q
                    ray = rays_through(camera, p % width + 0.5, p // width + 0.5)
                    rays[0, q], rays[1, q], rays[2, q] = ray.o0, ray.o1, ray.o2
                    rays[3, q], rays[4, q], rays[5, q] = ray.d0, ray.d1, ray.d2
                cast_batch(arrays, tree, stack, near, nearby, rays, pixels, best, best_t, colors,
                           lanes.t)  # fmt: skip
                for q in range(pixels):
                    index[p_first + q], t[p_first + q] = best[q], best_t[q]
        p_first += pixels


@njit(parallel=True, **MAKES_ARRAYS)
def cast_rays(arrays, tree, origins, directions, t_max):
    """:func:`nearest_hit` for each ray ``(N, 3)``: ``index (N,)``, ``t (N,)``, ``color (N, 3)``."""
    count = len(origins)
    index = np.empty(count, dtype=np.int64)
    t = np.empty(count)
    color = np.empty((count, 3))
    for chunk in prange((count + CHUNK - 1) // CHUNK):
        stack = new_stack()
        for i in range(chunk * CHUNK, min(count, (chunk + 1) * CHUNK)):
            o, d = origins[i], directions[i]
            hit = nearest_hit(arrays, tree, stack, o[0], o[1], o[2], d[0], d[1], d[2], t_max[i])
            index[i], t[i] = hit.index, hit.t
            color[i, 0], color[i, 1], color[i, 2] = hit.r, hit.g, hit.b
    return index, t, color


def caster(scene: Scene, arrays: Arrays | None = None) -> Callable[..., Hits]:
    """A :data:`raykit.shadows.Caster` over the whole scene: the nearest hits of any rays, as
    :func:`raykit.render.secondary_caster` gives them, found by :func:`cast_rays`."""
    arrays = arrays or scene_arrays(scene)
    tree = scene_tree(scene)

    def cast(origins, directions, t_max=None) -> Hits:
        t_max = np.full(len(origins), np.inf) if t_max is None else t_max
        # arrays of one kind, as _one_kind makes them: a new kind is a new compile
        origins, directions, t_max = (
            np.require(x, float, "CAW") for x in (origins, directions, t_max)
        )
        return Hits(*cast_rays(arrays, tree, origins, directions, t_max))

    return cast

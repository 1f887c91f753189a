"""The workers' jobs: how a render's pixels are cut into jobs (a screen tile's pixels, or a row of
image points), how a worker takes them (:func:`grain_taken`, the one loop every entry point of
:mod:`~raykit.engine.compiled.render` runs), where each job's results go (:class:`Film`) and
the rooms a worker keeps for its rays (:class:`RayRoom`, :class:`ShadingRoom`), made before its
call (:func:`flat_rooms` and the like); and the mean of
a pixel's samples (:func:`pixel_means`, which repeats :meth:`raykit.engine.regions.Image.mean`).
The threads that run the workers are :mod:`.pool`'s."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit
from numba.core import types
from numba.extending import intrinsic

from raykit.engine.compiled.bvh import DIRECT_HITS, new_stack
from raykit.engine.compiled.compiling import KERNEL, MAKES_ARRAYS, ONE_RAY
from raykit.engine.compiled.shading import Lanes, new_lanes
from raykit.engine.compiled.shadows import SHADOW_CANDIDATES
from raykit.engine.compiled.tiles import HOLDING_CHUNK

CHUNK = 256  # rays or pixels per parallel step: many per worker, and one stack each


@intrinsic
def take(typingctx, taken, count):
    """Atomically add ``count`` to ``taken[0]`` and return its value before: the first of the
    ``count`` jobs a worker takes (numba offers no atomic add on the CPU)."""

    def codegen(context, builder, signature, args):
        counter = context.make_array(signature.args[0])(context, builder, args[0])
        return builder.atomic_rmw("add", counter.data, args[1], "monotonic")

    return types.int64(taken, types.int64), codegen


@njit(**KERNEL)
def grain_taken(work, grain):
    """The next grain of jobs of ``work`` (a :class:`Work`) that one worker takes, into
    ``grain (2,)``: the jobs ``work.jobs[grain[0]:grain[1]]``, ``work.grain`` of them (fewer at
    the end), taken from the counter ``work.taken`` that every worker of the call shares
    (:func:`take`) whenever the worker is free, so that a worker slowed by other work takes fewer;
    each job is taken by exactly one worker. False once no job is left. Every entry point of
    :mod:`~raykit.engine.compiled.render` loops over it, as ``while grain_taken(work, grain):
    for j in range(grain[0], grain[1])``, its ``grain`` made once per worker (a plain kernel,
    not a generator: numba caches no generator on disk, and compiled it again in every
    process)."""
    count = len(work.jobs)
    first = take(work.taken, work.grain)
    grain[0], grain[1] = first, min(count, first + work.grain)
    return first < count


class Work(NamedTuple):
    """The jobs of one call of an entry point and how its workers share them
    (:func:`~.pool.shares`): ``jobs (J,)`` (tile numbers, CHUNKs of image points, or a
    distributed render's first pixels), the ``grain`` of jobs a worker takes at a time, and the
    counter ``taken (1,)`` of the jobs taken so far (:func:`grain_taken`)."""

    jobs: np.ndarray
    grain: int
    taken: np.ndarray


class Film(NamedTuple):
    """The image a call of :func:`~.render.trace_flat` or :func:`~.render.trace_lit` exposes: its
    ``width`` and ``height``, the image points ``xs``, ``ys`` (empty: whole tiles' pixels, see
    :func:`~.render.trace_flat`), the sample ``offsets (S, 2)`` and the ``centre`` sample (-1: a ray
    of its own), and where the results go, ``rgb (P, 3)``, ``index`` and ``t (P,)`` (both empty:
    the picture alone, see :func:`keeps_hits`). The scene's
    arrays travel beside it, not in it: a kernel called once a job is passed only what it reads
    (every array is a handful of numbers at each call). Made once a call, for all its workers."""

    width: int
    height: int
    xs: np.ndarray
    ys: np.ndarray
    offsets: np.ndarray
    centre: int
    rgb: np.ndarray
    index: np.ndarray
    t: np.ndarray


class TileJob(NamedTuple):
    """One job of :func:`~.render.trace_flat` or :func:`~.render.trace_lit` (:func:`job_of`):
    ``rows`` x ``across`` pixels, the upper-left one at (``left``, ``top``), in ``tile``; or
    (``tile`` -1) a row of image points from point ``first``, each in whichever tile holds it."""

    first: int
    rows: int
    top: int
    left: int
    across: int
    tile: int


@njit(**ONE_RAY)
def keeps_hits(film):
    """Whether ``film`` keeps each pixel's object index and t: not where its ``index`` and ``t``
    are empty (a render of the picture alone, ``hits=False`` in :func:`raykit.render.render`),
    which then casts no ray for them."""
    return len(film.t) > 0


@njit(**ONE_RAY)
def centre_rays(film):
    """1 where ``film`` casts a ray of its own through each pixel centre, for its object index and
    t: where no sample is the centre (``centre`` -1) and the film keeps them; else 0."""
    return 1 if film.centre < 0 and keeps_hits(film) else 0


@njit(**ONE_RAY)
def job_pixel(film, job, down, along):
    """The pixel ``down`` rows and ``along`` columns into ``job`` (a :class:`TileJob`):
    ``(p, x, y)``, where its results go and its upper-left corner. (Rows and columns, not a
    running count: an integer division per pixel cost more than its ray.)"""
    if len(film.xs):
        q = job.first + down * job.across + along
        return q, film.xs[q], film.ys[q]
    top, left = job.top + down, job.left + along
    return top * film.width + left, float(left), float(top)


@njit(**KERNEL)
def job_of(work, j, tiles, film):
    """Job ``work.jobs[j]`` (:class:`Work`) of :func:`~.render.trace_flat` or
    :func:`~.render.trace_lit`, a :class:`TileJob`: a tile's pixels, or a row of CHUNK of the
    image points of ``film`` (:class:`Film`)."""
    points = len(film.xs)
    if points:
        first = work.jobs[j] * CHUNK
        return TileJob(first, 1, 0, 0, min(CHUNK, points - first), -1)
    size = tiles.size
    tile = work.jobs[j]
    top = (tile // tiles.tiles_x) * size
    left = (tile % tiles.tiles_x) * size
    return TileJob(0, min(size, film.height - top), top, left, min(size, film.width - left), tile)


@njit(**KERNEL)
def background_job(film, job, empty):
    """A tile that no object's screen rectangle meets: its pixels get ``empty (3,)``, index -1
    and t = inf, and no ray."""
    rgb, index, t = film.rgb, film.index, film.t
    hits = keeps_hits(film)
    for down in range(job.rows):
        for along in range(job.across):
            p = (job.top + down) * film.width + job.left + along
            rgb[p, 0], rgb[p, 1], rgb[p, 2] = empty[0], empty[1], empty[2]
            if hits:
                index[p], t[p] = -1, np.inf


@njit(**KERNEL)
def job_points(film, job, xy):
    """Each of a job's rays' image points into ``xy (2, N)``: ray i is sample i % S of the
    job's pixel i // S; the rays through the pixel centres, if cast apart (:func:`centre_rays`),
    come after all those. Returns how many rays."""
    offsets = film.offsets
    samples = len(offsets)
    pixels = job.rows * job.across
    extra = centre_rays(film)
    if samples == 1 and not extra and len(film.xs) == 0:  # a tile's pixels, one point each
        along_x, down_y = offsets[0, 0], offsets[0, 1]
        for down in range(job.rows):
            y = float(job.top + down) + down_y
            row = np.uint64(down * job.across)  # unsigned, as primary_rays' loops say why
            for along in range(np.uint64(job.across)):
                xy[0, row + along] = float(job.left) + float(along) + along_x
                xy[1, row + along] = y
        return pixels
    for down in range(job.rows):
        for along in range(job.across):
            q = down * job.across + along
            _, px, py = job_pixel(film, job, down, along)
            for sample in range(samples):  # offsets in [0, 1): the point stays in its tile
                i = q * samples + sample
                xy[0, i], xy[1, i] = px + offsets[sample, 0], py + offsets[sample, 1]
            if extra:
                i = pixels * samples + q
                xy[0, i], xy[1, i] = px + 0.5, py + 0.5
    return pixels * (samples + extra)


@njit(**KERNEL)
def pixel_means(film, job, colors, best, best_t):
    """Each of a job's pixels: the mean of its samples' ``colors (3, N)`` (laid out as
    :func:`job_points` lays out the rays) into ``rgb``, and the object index and t of the ray
    through its centre into ``index`` and ``t``, where it keeps them (:func:`keeps_hits`)."""
    rgb, index, t, centre = film.rgb, film.index, film.t, film.centre
    samples = len(film.offsets)
    pixels = job.rows * job.across
    hits = keeps_hits(film)
    if samples == 1 and centre == 0:  # one sample, through the centre: as below, without /1
        for down in range(job.rows):
            first, _, _ = job_pixel(film, job, down, 0)  # a row's pixels lie side by side
            # unsigned, as primary_rays' loops say why
            row_p, row_q = np.uint64(first), np.uint64(down * job.across)
            for along in range(np.uint64(job.across)):
                p, q = row_p + along, row_q + along
                rgb[p, 0] = 0.0 + colors[0, q]
                rgb[p, 1] = 0.0 + colors[1, q]
                rgb[p, 2] = 0.0 + colors[2, q]
                if hits:
                    index[p], t[p] = best[q], best_t[q]
        return
    for down in range(job.rows):
        for along in range(job.across):
            q = down * job.across + along
            p, _, _ = job_pixel(film, job, down, along)
            r_sum, g_sum, b_sum = 0.0, 0.0, 0.0
            for sample in range(samples):
                i = q * samples + sample
                r_sum += colors[0, i]
                g_sum += colors[1, i]
                b_sum += colors[2, i]
            rgb[p, 0] = r_sum / samples
            rgb[p, 1] = g_sum / samples
            rgb[p, 2] = b_sum / samples
            if hits:
                i = pixels * samples + q if centre < 0 else q * samples + centre
                index[p], t[p] = best[i], best_t[i]


class SampleRoom(NamedTuple):
    """Room for a distributed render's samples' uniform numbers: each sample's ``numbers`` (a row
    each, ``(N, D)``, or ``(D,)`` for one sample at a time), the wanted ones copied into ``columns
    (D, N)`` (no columns for one at a time), what each pixel's samples share, ``keys (P, D // 2 + 2,
    6)`` (:func:`~.noise.pixel_keys`; P = 1 for one at a time), the objects a batch of a
    pinhole's samples can hit, ``near (DIRECT_HITS,)`` (:func:`~.tiles.row_objects`), and, for
    :func:`~.noise.sobol_numbers`, each sample's Sobol' cell and point in one pair of dimensions,
    ``cells (N,)`` and ``points (N,)``, its pixel's scrambling seeds of the pair, ``seeds (2,
    N)`` (uint32 each), and its pixel's round keys of the pair's shuffle, ``rounds (4, N)``
    (uint64). Each worker has its own, made before its call (:func:`new_sample_room`,
    :func:`sampled_rooms`)."""

    numbers: np.ndarray
    columns: np.ndarray
    keys: np.ndarray
    near: np.ndarray
    cells: np.ndarray
    points: np.ndarray
    seeds: np.ndarray
    rounds: np.ndarray


@njit(**MAKES_ARRAYS)
def new_sample_room(n, dimensions, pixels):
    """A :class:`SampleRoom` for ``n`` samples in lanes of ``dimensions`` numbers each, of
    ``pixels`` pixels at most, or, ``n`` 0, for one sample at a time."""
    numbers = np.empty((max(n, 1), dimensions))
    keys = np.zeros((max(pixels, 1), dimensions // 2 + 2, 6), dtype=np.uint64)
    near = np.empty(DIRECT_HITS, dtype=np.int64)
    cells, points = np.empty(n, dtype=np.uint32), np.empty(n, dtype=np.uint32)
    seeds, rounds = np.empty((2, n), dtype=np.uint32), np.empty((4, n), dtype=np.uint64)
    return SampleRoom(numbers, np.empty((dimensions, n)), keys, near, cells, points, seeds,
                      rounds)  # fmt: skip


class RayRoom(NamedTuple):
    """Room for a job's N rays: each ray's image point ``xy (2, N)``, origin and direction
    ``rays (6, N)``, its hit's object index ``best (N,)`` and ``best_t (N,)``, colour ``colors
    (3, N)``, whether it was ``made`` (:func:`~.tiles.primary_ray`), room ``ts``, ``alphas`` and
    ``betas`` for :func:`~.tiles.primary_rays`, and ``holding (HOLDING_CHUNK,)`` for
    :func:`~.tiles.primary_ray`. Each worker has its own, made before its call
    (:func:`new_ray_room`, :func:`flat_rooms`)."""

    xy: np.ndarray
    rays: np.ndarray
    best: np.ndarray
    best_t: np.ndarray
    colors: np.ndarray
    made: np.ndarray
    ts: np.ndarray
    alphas: np.ndarray
    betas: np.ndarray
    holding: np.ndarray


class ShadingRoom(NamedTuple):
    """Room for shading a job's rays: a tree walk's ``stack`` (:func:`new_stack`), the ``box
    (2, 3)`` of the surface points, each light's shadow list ``candidates (L,
    SHADOW_CANDIDATES)`` and ``counts (L,)`` (-1: no list, walk the tree), a shadow ``volume
    (6, 5)`` (:func:`~.shadows.shadow_lists`), and the ``lanes`` (:class:`Lanes`)."""

    stack: np.ndarray
    box: np.ndarray
    candidates: np.ndarray
    counts: np.ndarray
    volume: np.ndarray
    lanes: Lanes


@njit(**MAKES_ARRAYS)
def new_ray_room(n):
    """A :class:`RayRoom` for ``n`` rays."""
    return RayRoom(np.empty((2, n)), np.empty((6, n)), np.empty(n, dtype=np.int64),
                   np.empty(n), np.empty((3, n)), np.empty(n, dtype=np.bool_), np.empty(n),
                   np.empty(n), np.empty(n), np.empty(HOLDING_CHUNK, dtype=np.int64))  # fmt: skip


@njit(**MAKES_ARRAYS)
def new_shading_room(n, shading):
    """A :class:`ShadingRoom` for shading ``n`` rays of a scene with ``shading``
    (:class:`~.scene.Shading`)."""
    lists = len(shading.point_light) if shading.shadows else 0
    return ShadingRoom(new_stack(), np.empty((2, 3)),
                       np.empty((lists, SHADOW_CANDIDATES), dtype=np.int64),
                       np.full(len(shading.point_light), -1, dtype=np.int64), np.empty((6, 5)),
                       new_lanes(n))  # fmt: skip


# Each worker's rooms, the last arguments of its call of an entry point of
# raykit.engine.compiled.render: made here, before the call, by the kernels above (called from
# Python, each returns its named tuple), so that an entry point makes no array and counts no
# references (a KERNEL, into which its job is copied: compiling.JOB). Each ends with the worker's
# grain (2,) (grain_taken).


def flat_rooms(n: int) -> tuple[RayRoom, np.ndarray]:
    """A worker's rooms for :func:`~raykit.engine.compiled.render.trace_flat`: for a job's ``n``
    rays (:class:`RayRoom`), and its grain."""
    return new_ray_room(n), np.zeros(2, np.int64)


def lit_rooms(n: int, shading) -> tuple[RayRoom, ShadingRoom, np.ndarray]:
    """A worker's rooms for :func:`~raykit.engine.compiled.render.trace_lit`: for a job's ``n``
    rays and for shading them in a scene with ``shading`` (:class:`~.scene.Shading`), and its
    grain."""
    return new_ray_room(n), new_shading_room(n, shading), np.zeros(2, np.int64)


def sampled_rooms(
    n: int, pixels: int, shading, noise
) -> tuple[RayRoom, ShadingRoom, SampleRoom, np.ndarray]:
    """A worker's rooms for :func:`~raykit.engine.compiled.render.trace_sampled`: as
    :func:`lit_rooms`, for ``n`` samples of ``pixels`` pixels at most at a time, with room for
    their numbers in lanes of ``noise.dimensions`` (:class:`~.noise.Noise`), and its grain."""
    return (new_ray_room(n), new_shading_room(n, shading),
            new_sample_room(n, noise.dimensions, pixels), np.zeros(2, np.int64))  # fmt: skip


def moving_rooms(arrays, noise) -> tuple[np.ndarray, SampleRoom, np.ndarray, np.ndarray]:
    """A worker's rooms for :func:`~raykit.engine.compiled.render.trace_moving`: a tree walk's
    stack, room for one sample's numbers, its own copy of the centres ``(S, 3)`` of the spheres
    of ``arrays`` (:class:`~.scene.Arrays`), which it moves to each ray's time, and its grain."""
    return (new_stack(), new_sample_room(0, noise.dimensions, 1), arrays.centers.copy(),
            np.zeros(2, np.int64))  # fmt: skip

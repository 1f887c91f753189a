"""Repeats :mod:`raykit.engine.tiles` and :mod:`raykit.engine.screen_bounds` for primary
rays: each screen tile's objects, nearest first, and the viewing rays of a tile traced
against them, one at a time (:func:`primary_ray`) or in packets (:func:`primary_rays`)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from raykit.engine.compiled.billboards import billboard_color_at, hit_billboard
from raykit.engine.compiled.camera import rays_through
from raykit.engine.compiled.compiling import INLINED, KERNEL, MAKES_ARRAYS, ONE_RAY
from raykit.engine.compiled.hits import NearestHit, keep_nearer
from raykit.engine.compiled.rays import Ray
from raykit.engine.compiled.scene import Arrays
from raykit.engine.compiled.spheres import hit_sphere
from raykit.engine.screen_bounds import scene_bounds
from raykit.rays import dot, length
from raykit.scene import Scene


@njit(**MAKES_ARRAYS)
def bin_by_tile(bounds, closest, by_distance, tiles_x, tiles_y, size):
    """Each tile's objects, for primary rays: the objects ``by_distance (K,)`` (nearest first)
    whose screen rectangle ``bounds (K, 4)`` (x0, x1, y0, y1; NaN: never seen,
    :func:`raykit.engine.screen_bounds.scene_bounds`) meets the tile of ``size`` x ``size``
    pixels. Returns ``start (tiles + 1,)``, ``objects (E,)``: tile k's are
    objects[start[k]:start[k+1]], nearest first; and each of those entries' rectangle and
    ``closest`` t, ``entries (E, 5)``, kept beside it so that a pixel reads its tile's list
    straight through."""
    count = np.zeros(tiles_x * tiles_y + 1, dtype=np.int64)
    for fill in (False, True):  # count, then fill
        if fill:
            start = np.cumsum(count)
            cursor = start[:-1].copy()
            objects = np.empty(start[-1], dtype=np.int64)
            entries = np.empty((start[-1], 5))
        else:
            start = count
            cursor = count[:0]
            objects = np.empty(0, dtype=np.int64)
            entries = np.empty((0, 5))
        for obj in by_distance:
            x0, x1, y0, y1 = bounds[obj, 0], bounds[obj, 1], bounds[obj, 2], bounds[obj, 3]
            if not (x0 <= x1 and y0 <= y1):
                continue
            left, right = max(0, int(x0 // size)), min(tiles_x - 1, int(x1 // size))
            top, bottom = max(0, int(y0 // size)), min(tiles_y - 1, int(y1 // size))
            for ty in range(top, bottom + 1):
                for tx in range(left, right + 1):
                    tile = ty * tiles_x + tx
                    if fill:
                        k = cursor[tile]
                        objects[k] = obj
                        entries[k, 0], entries[k, 1], entries[k, 2], entries[k, 3] = x0, x1, y0, y1
                        entries[k, 4] = closest[obj]
                        cursor[tile] += 1
                    else:
                        count[tile + 1] += 1
    return start, objects, entries


class Tiles(NamedTuple):
    """The primary rays' skip (:func:`screen_tiles`): tile k (``size`` x ``size`` pixels,
    ``tiles_x`` to a row) lists the objects ``objects[start[k]:start[k + 1]]``, nearest first,
    each with its screen rectangle and closest t in ``entries (E, 5)``: (x0, x1, y0, y1,
    closest); a tile's rays go in ``packets`` (:func:`primary_rays`) or one at a time."""

    start: np.ndarray
    objects: np.ndarray
    entries: np.ndarray
    tiles_x: int
    size: int
    packets: bool


HOLDING_CHUNK = 8  # entries of a tile's list that primary_ray checks at a time (chosen by
# python benchmarks/thresholds.py, docs/benchmarks/thresholds.md)


class ViewingHit(NamedTuple):
    """:func:`primary_ray`'s answer for one viewing ray: whether the ray was ``made``, its
    ``nearest`` hit (a :class:`~raykit.engine.compiled.hits.NearestHit`: no object, at inf,
    the background's colour, if none) and the ``ray`` (a
    :class:`~raykit.engine.compiled.rays.Ray`, all 0 if not made)."""

    made: bool
    nearest: NearestHit
    ray: Ray


@njit(**INLINED)
def primary_ray(arrays, tiles, camera, x, y, tile, holding):
    """:func:`nearest_hit` for the viewing ray through image point (x, y), from the list of its
    tile (:func:`screen_tiles`; -1: the tile is found from x and y): only the objects whose
    screen rectangle holds the point (as :meth:`raykit.engine.tiles.Region.holding` decides),
    nearest first, until the next can only be farther than the hit found. The ray is made at
    the first rectangle that holds the point: if none does, it would see the background, and is
    not made at all (as in :meth:`raykit.engine.regions.Plan.viewing_rays`). Returns a
    :class:`ViewingHit`.

    The list is read HOLDING_CHUNK entries at a time: first which of them hold the point, into
    ``holding (HOLDING_CHUNK,)``, with no branch, then those in order. In a crowded picture an
    entry holds the point one time in two or three, and a branch per entry, guessed wrong that
    often, costs more than the checks (``python benchmarks/thresholds.py`` times a chunk of 1, a
    branch per entry, against larger ones). The objects offered are the same, in the same order:
    the lists are sorted by closest t, which is not NaN where the scene's numbers are finite (as
    :mod:`raykit.io` checks every scene file's), and the nearest hit only comes nearer, so an
    entry checked past the one a scan entry by entry stops at can only be farther than the hit,
    and is not offered either (tests/compiled/test_tiles.py compares the two scans)."""
    size, entries, objects = tiles.size, tiles.entries, tiles.objects
    background = arrays.background
    hit = NearestHit(index=np.int64(-1), t=np.inf, r=background[0], g=background[1],
                     b=background[2])  # fmt: skip
    made = False
    ray = Ray(o0=0.0, o1=0.0, o2=0.0, d0=0.0, d1=0.0, d2=0.0)
    if tile < 0:
        tile = (int(y) // size) * tiles.tiles_x + int(x) // size
    first, end = tiles.start[tile], tiles.start[tile + 1]
    while first < end:
        stop = min(end, first + HOLDING_CHUNK)
        held = 0
        for k in range(first, stop):  # & not `and`: no branch
            holding[held] = k
            held += (
                (entries[k, 0] <= x)
                & (x <= entries[k, 1])
                & (entries[k, 2] <= y)
                & (y <= entries[k, 3])
            )
        for i in range(held):
            k = holding[i]
            if entries[k, 4] > hit.t:
                break  # every object from here on is farther than the hit
            if not made:
                ray = rays_through(camera, x, y)
                made = True
            hit = keep_nearer(arrays, objects[k], ray, hit)
        if entries[stop - 1, 4] > hit.t:
            break
        first = stop
    return ViewingHit(made=made, nearest=hit, ray=ray)


@njit(**ONE_RAY)
def lane_offer(best, best_t, x, y, entry, obj, t):
    """:func:`~raykit.engine.compiled.hits.keep_nearer`'s rule for one lane of
    :func:`primary_rays`, offered object ``obj`` of its tile's list with its ``entry``, the
    tuple (x0, x1, y0, y1, closest) of its rectangle and its closest t, with the lane's hit
    of it at ``t``: whether the lane goes on (its nearest ``best_t`` not nearer than the object
    can be: :func:`primary_rays` says why that is the whole rule), whether the rectangle holds
    its image point (x, y), and whether ``obj`` is nearer than its ``best`` so far, or as near
    and of a lower index. The entry comes as numbers, read from the list once an object as the
    sphere's are, not as the list's row: the mask loop stores into the packet's arrays, and a
    row read through memory in the loop may have to be read again after each store."""
    x0, x1, y0, y1, closest = entry[0], entry[1], entry[2], entry[3], entry[4]
    still = closest <= best_t
    holds = still & (x0 <= x) & (x <= x1) & (y0 <= y) & (y <= y1)
    nearer = holds & ((t < best_t) | ((t == best_t) & (t < np.inf) & (obj < best)))
    return still, holds, nearer


@njit(**ONE_RAY)
def lanes_under(entry, job, samples, extra):
    """The lanes of a packet (:func:`primary_rays`) that the rectangle of ``entry`` (x0, x1, y0,
    y1, closest) can hold, as one run ``first:end`` of each of its two parts, ``(first, end,
    first_centre, end_centre)``: the pixels of ``job`` (a
    :class:`~raykit.engine.compiled.jobs.TileJob`) whose square [px, px + 1) x [py, py + 1)
    meets the rectangle lie in its rows and columns from the first such pixel to the last,
    and a pixel's ``samples`` lanes lie together (lane q·S + s), its ray through the centre,
    if cast apart (``extra`` 1), after all those (lane P·S + q). Every image point lies in
    its pixel's square, since sample offsets lie in [0, 1). Each run is widened to whole
    LANE_BLOCKs (the lanes of the packet's other pixels in it take nothing, as their points are
    not held); an empty run where no pixel meets the rectangle."""
    x0, x1, y0, y1 = entry[0], entry[1], entry[2], entry[3]  # within the image: finite
    first_column = int(max(0.0, math.floor(x0) - job.left))
    last_column = int(min(job.across - 1.0, math.floor(x1) - job.left))
    first_row = int(max(0.0, math.floor(y0) - job.top))
    last_row = int(min(job.rows - 1.0, math.floor(y1) - job.top))
    if first_column > last_column or first_row > last_row:
        return 0, 0, 0, 0
    first = first_row * job.across + first_column  # pixels
    end = last_row * job.across + last_column + 1
    pixels = job.rows * job.across
    lanes, block = pixels * (samples + extra), LANE_BLOCK
    first_centre, end_centre = pixels * samples + first, pixels * samples + end
    first, end = first * samples, end * samples
    return (first - first % block, min(lanes, end + -end % block),
            (first_centre - first_centre % block) * extra,
            min(lanes, end_centre + -end_centre % block) * extra)  # fmt: skip


# lanes_under widens each run to whole blocks of this many lanes: the vector loop takes that
# many at a time (a rest of a few lanes goes one at a time, without vector instructions)
LANE_BLOCK = 16


@njit(**ONE_RAY)
def farthest_hit(best_t, n):
    """The largest of ``best_t[:n]``, taken in four running maxima, so that each step need not
    wait for the one before (the compiler keeps a float maximum in order: NaN would change
    it; none is here, but it cannot know)."""
    far0, far1, far2, far3 = -np.inf, -np.inf, -np.inf, -np.inf
    fours = np.uint64(n - n % 4)  # unsigned, as primary_rays' loops say why
    one, two, three = np.uint64(1), np.uint64(2), np.uint64(3)  # unsigned plus signed is float
    for i in range(np.uint64(0), fours, np.uint64(4)):
        far0 = best_t[i] if best_t[i] > far0 else far0
        far1 = best_t[i + one] if best_t[i + one] > far1 else far1
        far2 = best_t[i + two] if best_t[i + two] > far2 else far2
        far3 = best_t[i + three] if best_t[i + three] > far3 else far3
    for i in range(fours, np.uint64(n)):
        far0 = best_t[i] if best_t[i] > far0 else far0
    return max(max(far0, far1), max(far2, far3))


HELD = -1.0  # in ts, for a lane the object's rectangle holds, whose hit is not nearer
NOT_HELD = -2.0  # for a lane the rectangle does not hold (a hit taken is t > 0)


@njit(**ONE_RAY)
def take_nearer(ts, start, end, obj, r, g, b, room):
    """Each lane of ``start:end`` whose ``ts`` is a hit (t >= 0, not HELD or NOT_HELD) takes it:
    object ``obj``, that t and the colour (r, g, b), into ``room`` (a
    :class:`~raykit.engine.compiled.jobs.RayRoom`); a lane held is ``made``. Returns how many
    lanes had no hit before, and how many took one. One loop per array written, each turned
    into vector instructions (a loop that writes several arrays is not: the compiler cannot
    tell that they do not overlap)."""
    best, best_t, colors, made = room.best, room.best_t, room.colors, room.made
    first_hits, taken = 0, 0
    for i in range(start, end):
        nearer = ts[i] >= 0.0
        first_hits += nearer & (best_t[i] == np.inf)
        taken += nearer
    if taken:
        for i in range(start, end):
            best_t[i] = ts[i] if ts[i] >= 0.0 else best_t[i]
        for i in range(start, end):
            best[i] = obj if ts[i] >= 0.0 else best[i]
        for i in range(start, end):
            colors[0, i] = r if ts[i] >= 0.0 else colors[0, i]
        for i in range(start, end):
            colors[1, i] = g if ts[i] >= 0.0 else colors[1, i]
        for i in range(start, end):
            colors[2, i] = b if ts[i] >= 0.0 else colors[2, i]
    for i in range(start, end):
        made[i] |= ts[i] >= HELD
    return first_hits, taken


@njit(**ONE_RAY)
def row_objects(tiles, width, first, last, out):
    """The objects a viewing ray through any point of pixels ``first`` to ``last`` (row-major,
    ``width`` to a row) can hit, for a pinhole's distributed samples, each a point of its own
    pixel: those of their screen tiles' lists (:func:`screen_tiles`) whose rectangle meets the
    pixels' (as :meth:`raykit.engine.tiles.Region.holding` would hold a point of them), each
    once, into ``out (K,)``. Returns their count, or -1 where the pixels are not of one row or
    more than K objects meet them: then every object may be hit, as far as the tiles tell."""
    row = first // width
    if last // width != row:
        return -1
    left, right = first - row * width, last - row * width + 1  # the pixels span [left, right]
    size = tiles.size
    count = 0
    for tile in range((row // size) * tiles.tiles_x + left // size,
                      (row // size) * tiles.tiles_x + (right - 1) // size + 1):  # fmt: skip
        for e in range(tiles.start[tile], tiles.start[tile + 1]):
            entry = tiles.entries[e]
            if entry[0] <= right and left <= entry[1] and entry[2] <= row + 1 and row <= entry[3]:
                obj = tiles.objects[e]
                listed = False
                for m in range(count):
                    listed = listed or out[m] == obj
                if not listed:
                    if count == len(out):
                        return -1
                    out[count] = obj
                    count += 1
    return count


@njit(**KERNEL)
def primary_rays(arrays, tiles, camera, job, samples, extra, room):
    """:func:`primary_ray` for every image point of ``room`` at once, all in the tile of ``job``
    (a :class:`~raykit.engine.compiled.jobs.TileJob`), laid out as
    :func:`~raykit.engine.compiled.jobs.job_points` lays them out (``samples`` a pixel, and
    ``extra`` 1 for a ray through each pixel's centre after those): a packet of rays, each a
    lane of arrays (a :class:`~raykit.engine.compiled.jobs.RayRoom`'s: points ``xy (2, L)`` in,
    ``rays (6, L)``, ``best (L,)``, ``best_t``, ``colors (3, L)``, ``made`` out; ``ts``,
    ``alphas``, ``betas`` room). The tile's objects are taken in turn, and each is tested
    against the lanes its screen rectangle can hold (:func:`lanes_under`), with one loop that
    the compiler turns into vector instructions (as many lanes at a time as the processor's
    vectors hold): a sphere's loop tests it (:func:`hit_sphere`) and keeps, for each lane, only
    what :func:`primary_ray` would take (:func:`lane_offer`: a lane whose rectangle does not
    hold its point, or whose hit is nearer than the object can be, takes nothing), writing
    only ``ts``, from which :func:`take_nearer` takes the hits; a billboard's loop tests it
    (:func:`hit_billboard`), a second keeps in ``ts`` what :func:`lane_offer` keeps, and its
    texel is looked up only for the lanes it would be nearer for
    (:func:`~raykit.engine.compiled.hits.keep_nearer`'s rule). So each lane offers the
    same objects in the same order as :func:`primary_ray` and gets the same bits.

    A lane goes on as :func:`primary_ray` does while the next object's closest t is not past
    its hit: the list is sorted by closest t and a hit only comes nearer, so once that fails
    it fails for every later object, and the test at each object is the whole rule. The
    packet stops where it fails for every lane: at an object whose closest t is past every
    lane's hit (:func:`farthest_hit`, looked for once no lane is without a hit). Every lane's
    ray is made (a lane that no rectangle holds is not ``made``, as in :func:`primary_ray`,
    and its ray is not used)."""
    xy, rays, best, best_t, colors = room.xy, room.rays, room.best, room.best_t, room.colors
    made, ts, alphas, betas = room.made, room.ts, room.alphas, room.betas
    background = arrays.background
    n = job.rows * job.across * (samples + extra)
    for i in range(n):
        ray = rays_through(camera, xy[0, i], xy[1, i])
        rays[0, i], rays[1, i], rays[2, i] = ray.o0, ray.o1, ray.o2
        rays[3, i], rays[4, i], rays[5, i] = ray.d0, ray.d1, ray.d2
    for i in range(n):
        best[i], best_t[i] = -1, np.inf
        colors[0, i], colors[1, i], colors[2, i] = background[0], background[1], background[2]
        made[i] = False
    spheres = len(arrays.radii)
    entries, objects = tiles.entries, tiles.objects
    centers, radii, sphere_colors = arrays.centers, arrays.radii, arrays.sphere_colors
    # lanes with no hit yet, whether a hit came nearer since the lanes' farthest hit was found
    unhit, nearer_since, farthest = n, False, np.inf
    for k in range(tiles.start[job.tile], tiles.start[job.tile + 1]):
        obj = objects[k]
        entry = (entries[k, 0], entries[k, 1], entries[k, 2], entries[k, 3], entries[k, 4])
        if nearer_since:  # a lane with no hit goes on to the end
            farthest, nearer_since = farthest_hit(best_t, n) if unhit == 0 else np.inf, False
        if entry[4] > farthest:
            break  # no lane goes on: every object from here on is farther than its hit
        runs = lanes_under(entry, job, samples, extra)
        for part in range(1 + extra):
            # unsigned: an index known not below 0 needs no wrap-around, which, unknown, kept
            # the loops from vector instructions
            start, end = np.uint64(runs[2 * part]), np.uint64(runs[2 * part + 1])
            if obj < spheres:
                c0, c1, c2, R = centers[obj, 0], centers[obj, 1], centers[obj, 2], radii[obj]
                for i in range(start, end):  # the vector loop: it writes one array only
                    t = hit_sphere(
                        rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i], rays[5, i],
                        c0, c1, c2, R,
                    )  # fmt: skip
                    _, holds, nearer = lane_offer(best[i], best_t[i], xy[0, i], xy[1, i],
                                                  entry, obj, t)  # fmt: skip
                    ts[i] = t if nearer else (HELD if holds else NOT_HELD)
                taken = take_nearer(ts, start, end, obj, sphere_colors[obj, 0],
                                    sphere_colors[obj, 1], sphere_colors[obj, 2], room)  # fmt: skip
                unhit -= taken[0]
                nearer_since |= taken[1] > 0
            else:
                board = obj - spheres
                for i in range(start, end):  # the vector loop: it writes only its three arrays
                    ts[i], alphas[i], betas[i] = hit_billboard(
                        rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i], rays[5, i],
                        arrays, board,
                    )  # fmt: skip
                for i in range(start, end):  # lane_offer in a vector loop, as the sphere's
                    _, holds, nearer = lane_offer(best[i], best_t[i], xy[0, i], xy[1, i],
                                                  entry, obj, ts[i])  # fmt: skip
                    ts[i] = ts[i] if nearer else (HELD if holds else NOT_HELD)
                for i in range(start, end):  # a texel only where the billboard is nearer
                    if ts[i] >= 0.0:
                        r, g, b, opaque = billboard_color_at(arrays, board, alphas[i], betas[i])
                        if opaque:
                            unhit -= best_t[i] == np.inf
                            best[i], best_t[i] = obj, ts[i]
                            colors[0, i], colors[1, i], colors[2, i] = r, g, b
                            nearer_since = True
                for i in range(start, end):  # held, as take_nearer marks it
                    made[i] |= ts[i] >= HELD


def screen_tiles(
    scene: Scene, arrays: Arrays, size: int | None = None, packets: bool | None = None
) -> Tiles:
    """The primary rays' skip: every object's screen rectangle
    (:func:`raykit.engine.screen_bounds.scene_bounds`, conservative), a lower bound on the t
    at which a viewing ray can meet it (``closest (K,)``: a sphere's distance from the eye less
    its radius, or in front of the image plane for orthographic rays, less a rounding margin; 0
    for a billboard), and each ``size`` x ``size`` tile's objects nearest first
    (:func:`bin_by_tile`), as :class:`Tiles`, whose rays go in ``packets``
    (:func:`primary_rays`) or one at a time (:func:`primary_ray`). Not given, both are
    :func:`tile_side`'s choice; a size given alone goes in packets from PACKET_SIDE up."""
    camera = scene.camera
    bounds = scene_bounds(camera, arrays.centers, arrays.radii, scene.billboards)
    if size is None:
        size, packets = tile_side(bounds, camera.width, camera.height)
    elif packets is None:
        packets = size >= PACKET_SIDE
    closest = np.zeros(scene.object_count)
    if scene.spheres:
        centers, radii = arrays.centers, arrays.radii
        eye = np.asarray(camera.eye, dtype=float)
        if camera.projection == "orthographic":
            distance = -dot(centers - eye, camera.frame[2])
        else:
            distance = length(centers - eye)
        margin = 1e-9 * (np.abs(distance) + radii + np.abs(eye).max() + np.abs(centers).max(axis=1))
        closest[: len(radii)] = np.maximum(0.0, distance - radii - margin)
    tiles_x = -(-camera.width // size)
    tiles_y = -(-camera.height // size)
    by_distance = np.argsort(closest, kind="stable")
    start, objects, entries = bin_by_tile(bounds, closest, by_distance, tiles_x, tiles_y, size)
    return Tiles(start, objects, entries, tiles_x, size, packets)


# which tiles primary rays take their objects from, and whether in packets (tile_side; timed by
# python benchmarks/engines.py --tile-sides, docs/benchmarks/tile_sides.md):
WIDE_SIDE = 16  # packets of this many pixels a side
PACKET_SIDE = 8  # or of this side (fewer rays fill too few vectors), whichever costs less,
PACKET_OBJECTS = 12  # where tiles of PACKET_SIDE list this many objects or fewer on average;
CROWDED_SIDE = 4  # else one ray at a time, in tiles of this side,
DENSE_SIDE = 2  # or of this one where those list more objects than they have pixels
# what a packet costs besides its rays' tests (its rays' image points, set-up, the call), in
# tests of one object against one ray: fitted to the 1-thread renders of classic and 1,000
# spheres at 1080p in packets of both sides (python benchmarks/compile_time.py --cpus native)
TILE_COST = 28


def packet_cost(bounds: np.ndarray, width: int, height: int, side: int) -> float:
    """What primary rays in packets of ``side`` x ``side`` pixels cost, in tests of one object
    against one ray, for the objects' screen rectangles ``bounds (K, 4)`` (those seen): each
    tile that lists objects (as :func:`bin_by_tile` lists them) tests each against all its
    side² rays, each ray costs one test more (made and summed into its pixel), and the tile
    TILE_COST; a tile that lists none costs nothing (its pixels get the background)."""
    tiles_x, tiles_y = -(-width // side), -(-height // side)
    left = np.maximum(0, np.floor(bounds[:, 0] / side)).astype(np.int64)
    right = np.minimum(tiles_x - 1, np.floor(bounds[:, 1] / side)).astype(np.int64)
    top = np.maximum(0, np.floor(bounds[:, 2] / side)).astype(np.int64)
    bottom = np.minimum(tiles_y - 1, np.floor(bounds[:, 3] / side)).astype(np.int64)
    meets = (left <= right) & (top <= bottom)
    left, right, top, bottom = left[meets], right[meets], top[meets], bottom[meets]
    # each rectangle +1 from its first tile on, a 2-D running sum: the objects each tile lists
    across = tiles_x + 1
    corners = np.concatenate(
        [top * across + left, top * across + right + 1, (bottom + 1) * across + left,
         (bottom + 1) * across + right + 1]
    )  # fmt: skip
    signs = np.repeat([1.0, -1.0, -1.0, 1.0], len(left))
    steps = np.bincount(corners, signs, minlength=(tiles_y + 1) * across)
    listed = steps.reshape(tiles_y + 1, across).cumsum(axis=0).cumsum(axis=1)[:tiles_y, :tiles_x]
    listing = listed[listed > 0]
    return float((side * side * (1.0 + listing) + TILE_COST).sum())


def tile_side(bounds: np.ndarray, width: int, height: int) -> tuple[int, bool]:
    """``(side, packets)`` for the objects' screen rectangles ``bounds (K, 4)`` on a ``width`` x
    ``height`` image. A packet (:func:`primary_rays`) tests each object of its tile against all its
    rays, several to a vector instruction, where one ray at a time (:func:`primary_ray`) tests only
    the objects whose rectangle holds the ray's point, with a branch each (on the objects, not on
    the entries checked for them, :func:`primary_ray`): packets win while a tile's list is short.
    The larger the packet, the fewer tiles' costs, but the more rays each object is tested against,
    and the fewer tiles see nothing. So: packets where tiles of PACKET_SIDE list PACKET_OBJECTS or
    fewer on average, of WIDE_SIDE or PACKET_SIDE, whichever :func:`packet_cost` finds cheaper, and
    else one ray at a time in CROWDED_SIDE tiles; in DENSE_SIDE ones where those list more
    objects than they have pixels on average. Each ray scans its tile's list, so a tile that lists
    more objects than it has rays spends more on scanning than a smaller tile, whose lists hold
    fewer of the small objects a dense picture is made of, spends on its more tiles.
    ``python benchmarks/engines.py --tile-sides`` times each choice
    (docs/benchmarks/tile_sides.md)."""
    seen = bounds[~np.isnan(bounds).any(axis=1)]

    def listed(side: int) -> float:  # objects in an average tile of this side
        across = np.floor(seen[:, 1] / side) - np.floor(seen[:, 0] / side) + 1
        down = np.floor(seen[:, 3] / side) - np.floor(seen[:, 2] / side) + 1
        return (across * down).sum() / (-(-width // side) * -(-height // side))

    if listed(PACKET_SIDE) > PACKET_OBJECTS:
        if listed(CROWDED_SIDE) > CROWDED_SIDE * CROWDED_SIDE:
            return DENSE_SIDE, False
        return CROWDED_SIDE, False
    wide = packet_cost(seen, width, height, WIDE_SIDE)
    if wide <= packet_cost(seen, width, height, PACKET_SIDE):
        return WIDE_SIDE, True
    return PACKET_SIDE, True

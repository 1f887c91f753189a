"""The screen tiles and primary rays (raykit.engine.compiled.tiles): packets and rays one at a time
against the numpy engine, and the choice of tile side."""

from __future__ import annotations

import numba
import numpy as np
import pytest
from libm_power import libm_power

from conftest import SCENES
from raykit.camera import rays_through
from raykit.engine import compiled
from raykit.engine.compiled.billboards import billboard_color_at, hit_billboard
from raykit.engine.compiled.spheres import hit_sphere
from raykit.engine.compiled.tiles import lane_offer, lanes_under
from raykit.io.scene_json import load_scene
from raykit.render import cast, render

from .harness import (
    crowd,
    exactly,
    packet_scenes,
    rays_into_crowd,
    ties_reversed,
    twin_test,
)

# every way of casting the viewing rays: tiles of each side, their rays in packets or one at a
# time (raykit.engine.compiled.tile_side picks one per scene); 4-pixel packets are too small to
# fill the vector loop, so they take its one-lane remainder, and 32 pixels its full vectors
TILINGS = [(4, False), (8, False), (4, True), (8, True), (16, True), (32, True)]


@pytest.mark.parametrize("samples", [1, 2])
@pytest.mark.parametrize(
    "name", ["cutouts", "orthographic", "classic_lit_at_1e6", "crowd_with_ties"]
)
def test_packets_and_rays_one_at_a_time_render_what_the_numpy_engine_renders(name, samples):
    scene = packet_scenes()[name]
    with libm_power():
        reference = render(scene, engine="numpy", samples=samples)
    prepared = compiled.prepare(scene)
    for side, packets in TILINGS:
        tiles = compiled.screen_tiles(scene, prepared.arrays, side, packets)
        assert (tiles.size, tiles.packets) == (side, packets)
        reversed_ties = ties_reversed(tiles)
        if name == "crowd_with_ties":  # its repeated spheres are listed the other way round
            assert not np.array_equal(reversed_ties.objects, tiles.objects)
            # and one ray at a time reads lists of several chunks (compiled.primary_ray)
            assert np.diff(tiles.start).max() > 2 * compiled.HOLDING_CHUNK
        for listed in (tiles, reversed_ties):
            rgb, index, t = compiled.render.render(prepared._replace(tiles=listed), samples)
            assert np.array_equal(index, reference.object_index), (side, packets)
            exactly(t, reference.t)
            exactly(rgb, reference.rgb)


def _scan_entry_by_entry(entries, x, y, t_of):
    """The objects a viewing ray through (x, y) offers, in order, scanning its tile's list
    ``entries (E, 5)`` one entry at a time, as primary_ray did before it read chunks; object
    k, if offered, is hit at ``t_of[k]``."""
    offered, best_t = [], np.inf
    for k, (x0, x1, y0, y1, closest) in enumerate(entries):
        if closest > best_t:
            break
        if x0 <= x <= x1 and y0 <= y <= y1:
            offered.append(k)
            best_t = min(best_t, t_of[k])
    return offered


def test_a_ray_reading_its_list_in_chunks_offers_what_a_scan_entry_by_entry_offers(monkeypatch):
    # primary_ray, run as Python with keep_nearer recording what it is given: lists of every length
    # around the chunk's, entries sorted nearest first as screen_tiles sorts them, some
    # holding the point and some hit
    rng = np.random.default_rng(23)
    offered, t_of = [], {}

    def recording_offer(arrays, obj, ray, hit):
        offered.append(obj)
        if t_of[obj] < hit.t:
            return hit._replace(index=obj, t=t_of[obj])
        return hit

    monkeypatch.setattr(compiled.tiles, "keep_nearer", recording_offer)  # primary_ray's own module
    monkeypatch.setattr(
        compiled.tiles, "rays_through", lambda camera, x, y: compiled.Ray(*(0.0,) * 6)
    )
    arrays = compiled.Arrays._make([np.zeros(3)] * len(compiled.Arrays._fields))
    chunk = compiled.HOLDING_CHUNK
    for length in [0, 1, chunk - 1, chunk, chunk + 1, 2 * chunk, 2 * chunk + 1, 5 * chunk + 3]:
        for _ in range(200):
            closest = np.sort(rng.uniform(0, 10, length))
            holds = rng.random(length) < 0.4
            entries = np.column_stack([
                np.where(holds, 0.0, 0.6), np.ones(length), np.zeros(length), np.ones(length),
                closest,
            ])  # fmt: skip
            hit = rng.random(length) < 0.5
            t_of = dict(enumerate(np.where(hit, closest + rng.uniform(0, 3, length), np.inf)))
            tiles = compiled.Tiles(np.array([0, length]), np.arange(length), entries, 1, 16, False)
            offered.clear()
            made = compiled.primary_ray.py_func(
                arrays, tiles, None, 0.5, 0.5, 0, np.empty(chunk, dtype=np.int64)
            ).made
            expected = _scan_entry_by_entry(entries, 0.5, 0.5, t_of)
            assert offered == expected, (length, closest, holds, hit)
            assert made == bool(expected)


@pytest.mark.parametrize("samples, extra", [(1, 0), (4, 1), (9, 0)])
def test_a_packet_tests_an_object_on_every_lane_its_rectangle_holds(samples, extra):
    """lanes_under's runs hold every lane whose image point (as job_points lays the lanes out:
    a pixel's samples together, the centre rays after them) the object's rectangle holds, on
    800 seeded rectangles over a tile of 5 x 7 pixels at (21, 13), some past its edges."""
    from raykit.engine.compiled.jobs import TileJob

    rng = np.random.default_rng(5)
    job = TileJob(first=0, rows=5, top=13, left=21, across=7, tile=0)
    offsets = rng.random((samples, 2))
    pixels = job.rows * job.across
    points = np.empty((pixels * (samples + extra), 2))
    for q in range(pixels):
        corner = (job.left + q % job.across, job.top + q // job.across)
        points[q * samples : (q + 1) * samples] = np.add(corner, offsets)
        if extra:
            points[pixels * samples + q] = np.add(corner, 0.5)
    for _ in range(800):
        x0, y0 = rng.uniform([17, 9], [31, 21])
        x1, y1 = x0 + rng.exponential(3), y0 + rng.exponential(3)
        if rng.random() < 0.1:  # edges on pixel boundaries
            x0, x1, y0, y1 = np.floor([x0, x1, y0, y1])
        held = np.flatnonzero(
            (x0 <= points[:, 0]) & (points[:, 0] <= x1)
            & (y0 <= points[:, 1]) & (points[:, 1] <= y1)
        )  # fmt: skip
        first, end, first_centre, end_centre = lanes_under(
            (x0, x1, y0, y1, 0.0), job, samples, extra
        )
        within = ((first <= held) & (held < end)) | ((first_centre <= held) & (held < end_centre))
        assert within.all(), (x0, x1, y0, y1, held[~within])
        assert end <= len(points) and end_centre <= len(points)


def test_tile_side_sends_rays_in_packets_unless_the_picture_is_crowded():
    classic = load_scene(SCENES / "classic.json")
    assert compiled.prepare(classic).tiles[-2:] == (compiled.WIDE_SIDE, True)
    width = height = 64
    rng = np.random.default_rng(3)
    # 1,000 squares 1 pixel wide on 64 x 64: 20 to an 8-pixel tile, 6 to a 4-pixel one
    corners = rng.uniform(0, 63, size=(1000, 2))
    dots = np.column_stack([corners[:, 0], corners[:, 0] + 1, corners[:, 1], corners[:, 1] + 1])
    assert compiled.tile_side(dots, width, height) == (compiled.CROWDED_SIDE, False)
    dense = np.concatenate([dots, dots + 0.25, dots + 0.5])  # 3,000: 19 to a 4-pixel tile
    assert compiled.tile_side(dense, width, height) == (compiled.DENSE_SIDE, False)
    corners = corners[:800] * 48 / 63  # 800 squares 16 pixels wide: 78 to a 4-pixel tile
    bounds = np.column_stack([corners[:, 0], corners[:, 0] + 16, corners[:, 1], corners[:, 1] + 16])
    assert compiled.tile_side(bounds, width, height) == (compiled.DENSE_SIDE, False)
    few = bounds[:160] / 4  # 160 squares 4 pixels wide: 10 to a 16-pixel tile, 4 to an 8
    assert compiled.tile_side(few, width, height) == (compiled.PACKET_SIDE, True)
    # 40 such squares leave most 8-pixel tiles empty, and an empty tile costs no ray
    assert compiled.tile_side(few[:40], width, height) == (compiled.PACKET_SIDE, True)
    # one square over most of the picture: every tile lists it, and fewer tiles cost less
    whole = np.array([[5.0, 60.0, 3.0, 58.0]])
    assert compiled.tile_side(whole, width, height) == (compiled.WIDE_SIDE, True)


@pytest.mark.parametrize("side", [4, 8, 16])
def test_packet_cost_counts_the_lists_the_tiles_get(side):
    """packet_cost's running sums count each tile's objects as bin_by_tile lists them (what
    it clips to the picture, what it leaves out), on 300 seeded rectangles, some off it."""
    rng = np.random.default_rng(11)
    width, height = 100, 70
    x0, y0 = rng.uniform(-30, 110, 300), rng.uniform(-30, 80, 300)
    bounds = np.column_stack([x0, x0 + rng.uniform(0, 40, 300), y0, y0 + rng.uniform(0, 40, 300)])
    order = np.arange(len(bounds))
    tiles_x, tiles_y = -(-width // side), -(-height // side)
    start, _, _ = compiled.tiles.bin_by_tile(
        bounds, np.zeros(len(bounds)), order, tiles_x, tiles_y, side
    )
    listed = np.diff(start)
    expected = (side * side * (1.0 + listed[listed > 0]) + compiled.tiles.TILE_COST).sum()
    assert compiled.tiles.packet_cost(bounds, width, height, side) == expected


def _tiled(side, packets):
    def check(rng):
        scene = crowd(rng, 60)
        with libm_power():
            reference = render(scene, engine="numpy")
        prepared = compiled.prepare(scene)
        tiles = compiled.screen_tiles(scene, prepared.arrays, side, packets)
        rgb, index, t = compiled.render.render(prepared._replace(tiles=tiles))
        assert np.array_equal(index, reference.object_index)
        exactly(t, reference.t)
        exactly(rgb, reference.rgb)

    return check


@numba.njit
def _offer_all_by_lane_offer(arrays, objects, origins, directions):
    """Each ray offered every object in index order, as raykit.render.cast offers them, each
    taken where lane_offer says it is nearer (and a billboard, opaque there), over a
    rectangle that holds every point: (index, t, whether every offer went on and held) per
    ray."""
    out = np.empty((len(origins), 3))
    entry = (-np.inf, np.inf, -np.inf, np.inf, 0.0)
    spheres = len(arrays.radii)
    for i in range(len(origins)):
        o, d = origins[i], directions[i]
        best, best_t, every = -1, np.inf, True
        for obj in range(objects):
            if obj < spheres:
                c = arrays.centers[obj]
                t = hit_sphere(o[0], o[1], o[2], d[0], d[1], d[2], c[0], c[1], c[2],
                               arrays.radii[obj])  # fmt: skip
                opaque = True
            else:
                t, alpha, beta = hit_billboard(o[0], o[1], o[2], d[0], d[1], d[2], arrays,
                                               obj - spheres)  # fmt: skip
                opaque = t < np.inf and billboard_color_at(arrays, obj - spheres, alpha, beta)[3]
            still, holds, nearer = lane_offer(best, best_t, 0.0, 0.0, entry, obj, t)
            every = every and still and holds
            if nearer and opaque:
                best, best_t = obj, t
        out[i, 0], out[i, 1], out[i, 2] = best, best_t, every
    return out


def _lane_offer(rng):
    """lane_offer's rule, offered every object in index order, keeps what cast keeps, exact
    ties (repeated spheres) and cut-out texels included."""
    from raykit.render import cast

    scene = crowd(rng, 30)
    origins, directions = rays_into_crowd(rng, 20_000)
    expected = cast(scene, origins, directions)
    got = _offer_all_by_lane_offer(compiled.scene_arrays(scene), scene.object_count, origins,
                                   directions)  # fmt: skip
    assert np.array_equal(got[:, 0], expected.index) and (expected.index >= 0).mean() > 0.05
    exactly(got[:, 1], expected.t)
    assert got[:, 2].all()  # no rectangle left a lane out, no closest t stopped one


def _bin_by_tile(rng):
    """Each tile's list holds the objects of the reference's region of the same pixels that
    can be seen in it (a subset: the compiled lists are cut to the tile's own pixels), nearest
    first, and every object a pixel centre of the tile sees."""
    from raykit.engine.tiles import TILE, regions

    scene = crowd(rng, 60)
    prepared = compiled.prepare(scene)
    tiles = compiled.screen_tiles(scene, prepared.arrays, TILE, False)
    seen = render(scene, engine="numpy").object_index
    closest = {}
    for k in range(len(tiles.objects)):
        closest[int(tiles.objects[k])] = tiles.entries[k, 4]
    for number, region in enumerate(regions(scene)):
        listed = tiles.objects[tiles.start[number] : tiles.start[number + 1]]
        assert set(listed) <= set(region.index_of[region.index_of >= 0])
        assert set(seen[region.pixels].ravel()) - {-1} <= set(listed)
        assert np.all(np.diff([closest[int(obj)] for obj in listed]) >= 0)


def _row_objects(rng):
    """A run of pixels in one row lists, once each, every object whose screen rectangle (the
    reference's, raykit.engine.screen_bounds) meets the pixels', so every object the numpy
    engine sees at a random point of them; and -1 for pixels of two rows, or more objects than
    its room holds."""
    from raykit.engine.screen_bounds import scene_bounds

    scene = crowd(rng, 60)
    arrays = compiled.scene_arrays(scene)
    camera = scene.camera
    width = camera.width
    tiles = compiled.screen_tiles(scene, arrays, 16, False)
    bounds = scene_bounds(camera, arrays.centers, arrays.radii, scene.billboards)
    kernels = compiled.tiles
    room = np.empty(scene.object_count, dtype=np.int64)
    listed_any = 0
    for _ in range(200):
        row = int(rng.integers(camera.height))
        left = int(rng.integers(width))
        right = int(rng.integers(left, min(width, left + 40)))  # the last pixel
        count = kernels.row_objects(tiles, width, row * width + left, row * width + right, room)
        with np.errstate(invalid="ignore"):
            meets = ((bounds[:, 0] <= right + 1) & (left <= bounds[:, 1])
                     & (bounds[:, 2] <= row + 1) & (row <= bounds[:, 3]))  # fmt: skip
        listed = room[:count]
        assert len(set(listed)) == count and set(listed) == set(np.flatnonzero(meets))
        xs = left + rng.uniform(0, right + 1 - left, 64)
        ys = row + rng.uniform(0, 1, 64)
        hits = cast(scene, *rays_through(camera, xs, ys)).index
        assert set(hits[hits >= 0]) <= set(listed)
        listed_any += count > 0
        if count > 1:
            small = np.empty(count - 1, dtype=np.int64)
            assert kernels.row_objects(tiles, width, row * width + left, row * width + right,
                                       small) == -1  # fmt: skip
    assert listed_any > 50
    assert kernels.row_objects(tiles, width, width - 1, width, room) == -1  # two rows


CHECKS = {
    "tiles.row_objects": _row_objects,
    "tiles.primary_ray": _tiled(4, False),
    "tiles.primary_rays": _tiled(8, True),
    "tiles.lane_offer": _lane_offer,
    "tiles.bin_by_tile": _bin_by_tile,
}
test_the_twin_repeats_its_reference = twin_test("tiles", CHECKS)

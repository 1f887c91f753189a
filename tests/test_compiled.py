"""The compiled engine (raykit.engine.compiled) against the reference, the numpy functions:
kernel by kernel on 10^5 seeded random rays and on the stability cases, bit for bit; then whole
renders, to the PNG byte; then the engine choice, the cache and the grader's independence.
Skipped where numba is not installed (CI runs them in a second lane with ".[fast]")."""

from __future__ import annotations

import contextlib
import io
import json
import os
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
from libm_power import libm_power

from conftest import REPO, SCENES, shifted_scene
from raykit import shading
from raykit.billboards import Billboard, billboard_color_at, hit_billboard
from raykit.camera import Camera, rays_through
from raykit.engine import choice
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.lights import DirectionalLight, PointLight
from raykit.materials import Material
from raykit.rays import normalize
from raykit.render import cast, render, secondary_caster
from raykit.scene import Scene
from raykit.spheres import Sphere, hit_sphere

numba = pytest.importorskip("numba")
compiled = pytest.importorskip("raykit.engine.compiled")

RAYS = 100_000
EPS = np.finfo(float).eps


@numba.njit
def _spheres(origins, directions, centers, radii):
    t = np.empty(len(origins))
    for i in range(len(origins)):
        o, d, c = origins[i], directions[i], centers[i]
        t[i] = compiled.hit_sphere(o[0], o[1], o[2], d[0], d[1], d[2], c[0], c[1], c[2], radii[i])
    return t


@numba.njit
def _boards(arrays, origins, directions, board):
    out = np.empty((len(origins), 3))
    for i in range(len(origins)):
        o, d = origins[i], directions[i]
        out[i] = compiled.hit_billboard(o[0], o[1], o[2], d[0], d[1], d[2], arrays, board)
    return out


@numba.njit
def _texels(arrays, board, alpha, beta):
    out = np.empty((len(alpha), 4))
    for i in range(len(alpha)):
        r, g, b, opaque = compiled.billboard_color_at(arrays, board, alpha[i], beta[i])
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = r, g, b, opaque
    return out


@numba.njit
def _viewing_rays(camera, x, y):
    out = np.empty((len(x), 6))
    for i in range(len(x)):
        out[i] = compiled.rays_through(camera, x[i], y[i])
    return out


def _random_rays(rng, count, scale=10.0):
    origins = rng.normal(size=(count, 3)) * scale
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return origins, directions


def _exactly(a, b):
    """Equal bit for bit, NaN where NaN, and the same sign of zero."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    same = (a == b) | (np.isnan(a) & np.isnan(b))
    assert same.all(), f"{(~same).sum()} of {a.size} differ, first at {np.argwhere(~same)[0]}"
    assert np.array_equal(np.signbit(a), np.signbit(b))


def test_sphere_kernel_repeats_hit_sphere_bit_for_bit_on_random_rays():
    rng = np.random.default_rng(18)
    origins, directions = _random_rays(rng, RAYS)
    aim = rng.uniform(0, 30, size=(RAYS, 1)) * directions  # half the rays pass near a centre
    centers = origins + aim + rng.normal(size=(RAYS, 3)) * rng.uniform(0, 3, size=(RAYS, 1))
    radii = rng.uniform(0.01, 4, size=RAYS)
    expected = hit_sphere(origins, directions, centers, radii)
    assert 0.2 < np.isfinite(expected).mean() < 0.9  # hits and misses both tested
    _exactly(_spheres(origins, directions, centers, radii), expected)


@pytest.mark.parametrize(
    "case",
    ["far_tiny", "grazing", "from_the_surface", "inside", "at_1e6", "unnormalised", "tie"],
)
def test_sphere_kernel_agrees_on_the_stability_cases(case):
    rng = np.random.default_rng(4)
    count = 20_000
    origins, directions = _random_rays(rng, count, 1.0)
    radii = np.full(count, 1.0)
    centers = origins + 5 * directions + rng.normal(size=(count, 3)) * 0.3
    if case == "far_tiny":  # a radius 1e-3 ball 1e5 away
        radii[:] = 1e-3
        centers = origins + 1e5 * directions + rng.normal(size=(count, 3)) * 1e-3
    elif case == "grazing":  # the line passes at exactly (to rounding) the radius
        side = np.cross(directions, rng.normal(size=(count, 3)))
        side /= np.linalg.norm(side, axis=1, keepdims=True)
        centers = origins + 5 * directions + side * radii[:, None]
    elif case == "from_the_surface":  # rays that start on the sphere, inwards and outwards
        normal = rng.normal(size=(count, 3))
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        centers = origins - normal
    elif case == "inside":
        centers = origins + rng.normal(size=(count, 3)) * 0.1
    elif case == "at_1e6":
        origins, centers = origins + 1e6, centers + 1e6
    elif case == "unnormalised":
        directions = directions * rng.uniform(1e-3, 1e3, size=(count, 1))
    elif case == "tie":  # rays along an axis, through the centre: both roots exact
        directions = np.tile([0.0, 0.0, 1.0], (count, 1))
        centers = origins + [0.0, 0.0, 3.0]
    expected = hit_sphere(origins, directions, centers, radii)
    _exactly(_spheres(origins, directions, centers, radii), expected)


def _board_scene(rng, texture=None):
    corner = rng.normal(size=3) * 3
    a, b = rng.normal(size=3) * 2, rng.normal(size=3) * 2
    board = Billboard(corner, corner + b, corner + a, color=rng.uniform(size=3), texture=texture)
    camera = Camera(np.zeros(3), np.array([0, 0, -1.0]), np.array([0, 1.0, 0]), 60, 8, 8)
    return Scene(camera, billboards=(board,)), board


@pytest.mark.parametrize("where", ["random", "edge_on", "at_1e6", "on_the_plane"])
def test_billboard_kernel_repeats_hit_billboard_bit_for_bit(where):
    rng = np.random.default_rng(7)
    scene, board = _board_scene(rng)
    count = RAYS if where == "random" else 20_000
    origins, directions = _random_rays(rng, count, 4.0)
    if where == "random":  # aimed at and around the parallelogram
        alpha, beta = rng.uniform(-0.3, 1.3, size=(2, count, 1))
        toward = board.upper_left + alpha * board.a + beta * board.b - origins
        directions = toward / np.linalg.norm(toward, axis=1, keepdims=True)
    elif where == "edge_on":  # directions in the billboard's plane: parallel to it
        directions = np.cross(board.n, rng.normal(size=(count, 3)))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    elif where == "at_1e6":
        scene, board = _board_scene(np.random.default_rng(7))
        moved = lambda p: np.asarray(p) + 1e6  # noqa: E731
        board = replace(
            board,
            upper_left=moved(board.upper_left),
            lower_left=moved(board.lower_left),
            upper_right=moved(board.upper_right),
        )
        scene = replace(scene, billboards=(board,))
        origins = origins + 1e6
    elif where == "on_the_plane":  # rays that start on the billboard
        alpha, beta = rng.uniform(size=(2, count, 1))
        origins = board.upper_left + alpha * board.a + beta * board.b
    t, alpha, beta = hit_billboard(origins, directions, board)
    got = _boards(compiled.scene_arrays(scene), origins, directions, 0)
    _exactly(got[:, 0], t)
    hit = np.isfinite(t)
    _exactly(got[hit, 1], alpha[hit])
    _exactly(got[hit, 2], beta[hit])
    if where == "random":
        assert 0.05 < hit.mean() < 0.9


class _Texels:
    def __init__(self, rgba):
        self.rgba, self.height, self.width = rgba, rgba.shape[0], rgba.shape[1]


def test_texel_kernel_repeats_the_nearest_texel_and_its_holes():
    rng = np.random.default_rng(9)
    rgba = rng.integers(0, 256, size=(7, 13, 4), dtype=np.uint8)
    scene, board = _board_scene(rng, texture=_Texels(rgba))
    alpha = np.concatenate([rng.uniform(size=RAYS), [0.0, 1.0, 0.5, 1 / 13, 12 / 13]])
    beta = np.concatenate([rng.uniform(size=RAYS), [0.0, 1.0, 1 / 7, 6 / 7, 0.5]])
    colors, opaque = billboard_color_at(board, alpha, beta)(np.arange(len(alpha)))
    got = _texels(compiled.scene_arrays(scene), 0, alpha, beta)
    _exactly(got[:, :3], colors)
    assert np.array_equal(got[:, 3] == 1, opaque) and 0.3 < opaque.mean() < 0.7


@pytest.mark.parametrize("projection", ["perspective", "orthographic"])
@pytest.mark.parametrize("far", [False, True])
def test_viewing_ray_kernel_repeats_rays_through(projection, far):
    rng = np.random.default_rng(11)
    for _ in range(5):
        eye = rng.normal(size=3) * (1e6 if far else 5)
        camera = Camera(
            eye, eye + rng.normal(size=3), rng.normal(size=3), rng.uniform(5, 120),
            int(rng.integers(1, 400)), int(rng.integers(1, 400)), projection,
        )  # fmt: skip
        x = rng.uniform(0, camera.width, size=RAYS // 5)
        y = rng.uniform(0, camera.height, size=RAYS // 5)
        origins, directions = rays_through(camera, x, y)
        scene = Scene(camera)
        got = _viewing_rays(compiled.camera_tuple(scene), x, y)
        _exactly(got[:, :3], origins)
        _exactly(got[:, 3:], directions)


def _crowd(rng, count, ties=True, holes=True):
    """A random scene of spheres and billboards with exact ties (repeated spheres) and
    cut-out textures."""
    spheres = [
        Sphere(rng.normal(size=3) * 4, float(rng.uniform(0.2, 1.5)), rng.uniform(size=3))
        for _ in range(count)
    ]
    if ties:
        spheres += [replace(s, color=rng.uniform(size=3)) for s in spheres[: count // 4]]
    boards = []
    for k in range(4):
        rgba = rng.integers(0, 256, size=(5, 6, 4), dtype=np.uint8)
        corner = rng.normal(size=3) * 4
        a, b = rng.normal(size=3) * 3, rng.normal(size=3) * 3
        texture = _Texels(rgba) if holes and k % 2 else None
        boards.append(Billboard(corner, corner + b, corner + a, rng.uniform(size=3), texture))
    camera = Camera(np.array([0, 0, 20.0]), np.zeros(3), np.array([0, 1.0, 0]), 40, 64, 48)
    return Scene(camera, tuple(spheres), tuple(boards), background=np.array([0.1, 0.2, 0.3]))


@pytest.mark.parametrize("objects", [3, 40, 300])
def test_bvh_caster_answers_what_cast_answers_with_ties_and_holes(objects):
    rng = np.random.default_rng(objects)
    scene = _crowd(rng, objects)
    if objects < 4:  # few enough that each ray tests every object (DIRECT_HITS): add a tie
        twin = replace(scene.spheres[0], color=np.array([1.0, 0.0, 1.0]))
        scene = replace(scene, spheres=(*scene.spheres, twin))
    direct = len(scene.spheres) + len(scene.billboards) <= compiled.DIRECT_HITS
    assert direct == (objects < 4)  # the small crowd takes that path, the others the tree's
    origins, directions = _random_rays(rng, RAYS, 6.0)
    toward = rng.normal(size=(RAYS, 3)) * 4 - origins  # aimed into the crowd
    directions = toward / np.linalg.norm(toward, axis=1, keepdims=True)
    expected = cast(scene, origins, directions)
    got = compiled.caster(scene)(origins, directions)
    assert np.array_equal(got.index, expected.index)
    _exactly(got.t, expected.t)
    _exactly(got.color, expected.color)
    assert (expected.index >= 0).mean() > 0.05  # thousands of hits, and misses
    assert (expected.index == 0).sum() > 25  # rays that meet sphere 0 and its twin at one t


@numba.njit
def _shade(arrays, tree, shading, origins, directions, index, t, color):
    out = np.empty((len(origins), 3))
    stack = compiled.new_stack()
    for i in range(len(origins)):
        o, d, c = origins[i], directions[i], color[i]
        out[i, 0], out[i, 1], out[i, 2] = compiled.shade(
            arrays, tree, shading, stack, o[0], o[1], o[2], d[0], d[1], d[2],
            index[i], t[i], c[0], c[1], c[2],
        )  # fmt: skip
    return out


def _lit_crowd(rng, count):
    """A crowd with a point light, a directional light, ambient light, and materials: some
    shiny, some mirrors, some with their own diffuse colour."""
    scene = _crowd(rng, count)

    def material(k):
        return Material(
            diffuse=rng.uniform(size=3) if k % 3 == 0 else None,
            specular=rng.uniform(size=3) if k % 2 else np.zeros(3),
            shininess=float(rng.choice([1.0, 8.0, 32.0, 100.0])),
            mirror=rng.uniform(0.2, 0.8, size=3) if k % 4 == 1 else np.zeros(3),
        )

    lights = (
        PointLight(np.array([3.0, 8.0, 10.0]), np.array([0.9, 0.8, 0.7])),
        DirectionalLight(np.array([-1.0, -2.0, -0.5]), np.array([0.3, 0.3, 0.4])),
    )
    return replace(
        scene,
        spheres=tuple(replace(s, material=material(k)) for k, s in enumerate(scene.spheres)),
        billboards=tuple(replace(b, material=material(k)) for k, b in enumerate(scene.billboards)),
        lights=lights,
        ambient=np.array([0.1, 0.1, 0.1]),
    )


def test_shading_kernel_repeats_shade_bit_for_bit_with_the_same_pow():
    rng = np.random.default_rng(45)
    scene = _lit_crowd(rng, 40)
    origins, directions = _random_rays(rng, RAYS, 6.0)
    toward = rng.normal(size=(RAYS, 3)) * 4 - origins
    directions = toward / np.linalg.norm(toward, axis=1, keepdims=True)
    hits = cast(scene, origins, directions)
    with libm_power():
        expected = shading.shade(scene, secondary_caster(scene), origins, directions, hits)
    got = _shade(
        compiled.scene_arrays(scene), compiled.scene_tree(scene), compiled.scene_shading(scene),
        origins, directions, hits.index, hits.t, hits.color,
    )  # fmt: skip
    _exactly(got, expected)
    assert (hits.index >= 0).mean() > 0.3
    reference = shading.shade(scene, secondary_caster(scene), origins, directions, hits)
    np.testing.assert_allclose(got, reference, rtol=4 * EPS, atol=0)


def _awkward_lights(rng, scene):
    """Lights that test the shadow lists' geometry: a point light inside the crowd and one
    inside a sphere, a directional light straight down the y axis (two zero components) and
    one at random."""
    inside = scene.spheres[0].center + 0.3 * scene.spheres[0].radius * normalize(rng.normal(size=3))
    return (
        PointLight(np.zeros(3), np.array([0.5, 0.4, 0.3])),
        PointLight(inside, np.array([0.2, 0.2, 0.2])),
        DirectionalLight(np.array([0.0, -1.0, 0.0]), np.array([0.3, 0.3, 0.3])),
        DirectionalLight(rng.normal(size=3), np.array([0.2, 0.3, 0.4])),
    )


@numba.njit(error_model="numpy")  # as the engine's: x / 0 is inf (a light along an axis)
def _in_lanes_and_one_by_one(arrays, tree, shading, p, n, d, error, lists):
    """Each tile's surface points ``p (T, P, 3)`` (normals n, view directions d, rounding
    bounds ``error (T, P)``; hits on object 0, flat colour 0.5) shaded in lanes as lit_job
    shades them (surface_lanes' start, then light_lanes), with the tile's shadow lists if
    ``lists``, else with every shadow ray walking the tree; and one by one by surface_color:
    both colours, and the lists' counts."""
    tiles, count = p.shape[0], p.shape[1]
    L = len(shading.point_light)
    in_lanes, one_by_one = np.empty((tiles, count, 3)), np.empty((tiles, count, 3))
    stack = compiled.new_stack()
    volume, box = np.empty((6, 5)), np.empty((2, 3))
    candidates = np.empty((L, compiled.SHADOW_CANDIDATES), dtype=np.int64)
    counts = np.full((tiles, L), -1, dtype=np.int64)
    lanes = compiled.new_lanes(count)
    lane_p, lane_n, lane_error = lanes.p, lanes.n, lanes.error
    lane_k, lane_total = lanes.k, lanes.total
    rays, best = np.zeros((6, count)), np.zeros(count, dtype=np.int64)
    k = shading.diffuse[0] if shading.has_diffuse[0] else np.full(3, 0.5)
    for tile in range(tiles):
        for axis in range(3):
            box[0, axis], box[1, axis] = p[tile, :, axis].min(), p[tile, :, axis].max()
            lane_p[axis], lane_n[axis], rays[3 + axis] = p[tile, :, axis], n[tile, :, axis], \
                d[tile, :, axis]  # fmt: skip
            lane_k[axis], lane_total[axis] = k[axis], k[axis] * shading.ambient[axis]
        lane_error[:] = error[tile]
        if lists and shading.shadows:
            pad = 2.0 * compiled.OFFSET_FACTOR * error[tile].max()
            compiled.shadow_lists(arrays, tree, shading, stack, box, pad, volume, candidates,
                                  counts[tile])  # fmt: skip
        compiled.light_lanes(
            arrays, tree, shading, stack, rays, best, count, lanes, candidates, counts[tile]
        )
        for i in range(count):
            in_lanes[tile, i] = lane_total[:, i]
            one_by_one[tile, i, 0], one_by_one[tile, i, 1], one_by_one[tile, i, 2] = \
                compiled.surface_color(
                    arrays, tree, shading, stack, 0, p[tile, i, 0], p[tile, i, 1], p[tile, i, 2],
                    n[tile, i, 0], n[tile, i, 1], n[tile, i, 2], d[tile, i, 0], d[tile, i, 1],
                    d[tile, i, 2], error[tile, i], 0.5, 0.5, 0.5,
                )  # fmt: skip
    return in_lanes, one_by_one, counts


def _grazing_tiles(rng, scene, lights, tiles, count):
    """Tiles of ``count`` surface points each, half in random boxes from 1e-3 to 5 across, half
    packed around a point whose ray to a light grazes a sphere (a tangent point, moved back
    along the ray), jittered by 1e-12 to 1e-3."""
    p = np.empty((tiles, count, 3))
    middle = np.mean([sphere.center for sphere in scene.spheres], axis=0)
    for k in range(tiles):
        if k % 2 == 0:
            corner = middle + rng.normal(size=3) * 4
            p[k] = corner + rng.uniform(size=(count, 3)) * 10 ** rng.uniform(-3, 0.7)
            continue
        sphere = scene.spheres[rng.integers(len(scene.spheres))]
        light = lights[rng.integers(len(lights))]
        if isinstance(light, PointLight):
            across = normalize(np.cross(rng.normal(size=3), sphere.center - light.position))
            tangent = sphere.center + sphere.radius * across
            start = light.position + (tangent - light.position) * rng.uniform(1.05, 3)
        else:
            l = -normalize(light.direction)  # noqa: E741  (the slide's l, toward the light)
            across = normalize(np.cross(l, rng.normal(size=3)))
            tangent = sphere.center + sphere.radius * across
            start = tangent - l * rng.uniform(0.1, 5)
        jitter = rng.normal(size=(count, 3)) * 10 ** rng.uniform(-12, -3)
        jitter[0] = 0.0  # one exactly grazing
        p[k] = start + jitter
    return p


@pytest.mark.parametrize("offset", [0.0, 1e6])
@pytest.mark.parametrize("crowd", [40, 60])  # 54 objects, each tested for the lists; 79: a tree
def test_shading_in_lanes_gives_every_surface_point_the_colour_surface_color_gives(crowd, offset):
    rng = np.random.default_rng(77 + crowd)
    people = _lit_crowd(rng, crowd)
    scene = shifted_scene(replace(people, lights=_awkward_lights(rng, people)), [offset] * 3)
    assert (scene.object_count <= compiled.DIRECT_LISTS) == (crowd == 40)
    arrays, shading, tree = (
        compiled.scene_arrays(scene), compiled.scene_shading(scene), compiled.scene_tree(scene)
    )  # fmt: skip
    tiles, count = 1200, 64  # 76,800 points, four shadow rays each
    p = _grazing_tiles(rng, scene, scene.lights, tiles, count)
    n = normalize(rng.normal(size=(tiles, count, 3)))
    d = normalize(rng.normal(size=(tiles, count, 3)))
    error = EPS * (np.abs(p).max(axis=2) + rng.uniform(1, 30, size=(tiles, count)))
    listed, one_by_one, counts = _in_lanes_and_one_by_one(
        arrays, tree, shading, p, n, d, error, True
    )
    _exactly(listed, one_by_one)
    # the lists were used, and the shadows they decide differ from point to point
    assert (counts >= 0).mean() > 0.5 and (counts == -1).any()
    walked, _, _ = _in_lanes_and_one_by_one(arrays, tree, shading, p, n, d, error, False)
    _exactly(walked, one_by_one)
    unshadowed = shading._replace(shadows=False)
    lit, _, _ = _in_lanes_and_one_by_one(arrays, tree, unshadowed, p, n, d, error, True)
    in_shadow = (lit != one_by_one).any(axis=2)
    assert 0.05 < in_shadow.mean() < 0.95


@pytest.mark.parametrize("samples", [1, 2])
@pytest.mark.parametrize("offset", [0.0, 1e6])
def test_lit_crowds_with_awkward_lights_render_the_same_with_both_engines(samples, offset):
    rng = np.random.default_rng(int(samples + offset % 97))
    crowd = _lit_crowd(rng, 30)
    scene = shifted_scene(replace(crowd, lights=_awkward_lights(rng, crowd)), [offset] * 3)
    _same_render(scene, samples=samples)


def _png(rgb) -> bytes:
    from PIL import Image

    from raykit.io.images import quantize

    buffer = io.BytesIO()
    Image.fromarray(quantize(rgb)).save(buffer, format="PNG")
    return buffer.getvalue()


def _same_render(scene, **options):
    """The compiled render is the numpy render bit for bit once both take the same pow, and
    within 4 units in the last place of it (the PNG bytes the same) as the reference stands."""
    fast = render(scene, engine="compiled", **options)
    with libm_power():
        same_pow = render(scene, engine="numpy", **options)
    assert np.array_equal(fast.object_index, same_pow.object_index)
    _exactly(fast.t, same_pow.t)
    _exactly(fast.rgb, same_pow.rgb)
    numpy_image = render(scene, engine="numpy", **options)
    np.testing.assert_allclose(fast.rgb, numpy_image.rgb, rtol=4 * EPS, atol=0)
    assert _png(fast.rgb) == _png(numpy_image.rgb)


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.json")), ids=lambda p: p.stem)
def test_every_example_scene_gives_the_same_png_bytes_with_both_engines(path):
    _same_render(load_scene(path))


@pytest.mark.parametrize("samples,adaptive", [(2, False), (3, False), (3, True)])
@pytest.mark.parametrize("name", ["classic", "cutouts", "mirror_balls", "orthographic"])
def test_samples_and_adaptive_sampling_give_the_same_image_with_both_engines(
    name, samples, adaptive
):
    scene = load_scene(SCENES / f"{name}.json")
    small = replace(scene, camera=replace(scene.camera, width=96, height=72))
    _same_render(small, samples=samples, adaptive=adaptive)


@pytest.mark.parametrize("objects", [5, 200])
def test_random_crowds_render_the_same_with_both_engines(objects):
    _same_render(_crowd(np.random.default_rng(objects + 1), objects))


def test_far_tiny_sphere_and_a_scene_at_1e6_render_the_same_with_both_engines():
    fov = float(np.degrees(4e-8))
    far = {
        "camera": {"eye": [0, 0, 1e5], "lookat": [2e-4, -1e-4, 0], "up": [0, 1, 0],
                   "fov_angle": fov, "width": 23, "height": 23},
        "spheres": [{"center": [0, 0, 0], "radius": 1e-3, "color": [1, 1, 1]}],
    }  # fmt: skip
    _same_render(scene_from_dict(far))
    data = json.loads((SCENES / "classic_lit.json").read_text())
    data.pop("$schema", None)
    moved = scene_from_dict(shifted_scene(data, [1e6, 1e6, 1e6]), folder=SCENES)
    _same_render(replace(moved, camera=replace(moved.camera, width=120, height=90)))


# every way of casting the viewing rays: tiles of each side, their rays in packets or one at a
# time (raykit.engine.compiled.tile_side picks one per scene); 4-pixel packets are too small to
# fill the vector loop, so they take its one-lane remainder, and 32 pixels its full vectors
TILINGS = [(4, False), (8, False), (4, True), (8, True), (16, True), (32, True)]


def _packet_scenes():
    rng = np.random.default_rng(7)
    data = json.loads((SCENES / "classic_lit.json").read_text())
    data.pop("$schema", None)
    moved = scene_from_dict(shifted_scene(data, [1e6, 1e6, 1e6]), folder=SCENES)
    small = lambda scene: replace(scene, camera=replace(scene.camera, width=70, height=45))  # noqa: E731
    return {
        "cutouts": small(load_scene(SCENES / "cutouts.json")),  # texels and holes
        "orthographic": small(load_scene(SCENES / "orthographic.json")),
        "classic_lit_at_1e6": small(moved),  # shaded, with shadow lists
        "crowd_with_ties": _crowd(rng, 200),
    }


@pytest.mark.parametrize("samples", [1, 2])
@pytest.mark.parametrize(
    "name", ["cutouts", "orthographic", "classic_lit_at_1e6", "crowd_with_ties"]
)
def test_packets_and_rays_one_at_a_time_render_what_the_numpy_engine_renders(name, samples):
    scene = _packet_scenes()[name]
    with libm_power():
        reference = render(scene, engine="numpy", samples=samples)
    prepared = compiled.prepare(scene)
    for side, packets in TILINGS:
        tiles = compiled.screen_tiles(scene, prepared.arrays, side, packets)
        assert (tiles.size, tiles.packets) == (side, packets)
        reversed_ties = _ties_reversed(tiles)
        if name == "crowd_with_ties":  # its repeated spheres are listed the other way round
            assert not np.array_equal(reversed_ties.objects, tiles.objects)
            # and one ray at a time reads lists of several chunks (compiled.primary_ray)
            assert np.diff(tiles.start).max() > 2 * compiled.HOLDING_CHUNK
        for listed in (tiles, reversed_ties):
            rgb, index, t = compiled.render(prepared._replace(tiles=listed), samples)
            assert np.array_equal(index, reference.object_index), (side, packets)
            _exactly(t, reference.t)
            _exactly(rgb, reference.rgb)


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

    def recording_offer(arrays, obj, o0, o1, o2, d0, d1, d2, best, best_t, r, g, b):
        offered.append(obj)
        if t_of[obj] < best_t:
            return obj, t_of[obj], r, g, b
        return best, best_t, r, g, b

    monkeypatch.setattr(compiled.tiles, "keep_nearer", recording_offer)  # primary_ray's own module
    monkeypatch.setattr(compiled.tiles, "rays_through", lambda camera, x, y: (0.0,) * 6)
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
            made, *_ = compiled.primary_ray.py_func(
                arrays, tiles, None, 0.5, 0.5, 0, np.empty(chunk, dtype=np.int64)
            )
            expected = _scan_entry_by_entry(entries, 0.5, 0.5, t_of)
            assert offered == expected, (length, closest, holds, hit)
            assert made == bool(expected)


@numba.njit(parallel=True)
def _times_taken(jobs, grain, workers):
    """How often each worker takes each of ``jobs`` when ``workers`` cores take ``grain`` at a
    time from one counter, as compiled.trace's workers do: ``(workers, jobs)``, a row each, so
    that two workers' counts of one job never share a write."""
    taken = np.zeros(1, dtype=np.int64)
    arrived = np.zeros(1, dtype=np.int64)
    times = np.zeros((workers, jobs), dtype=np.int64)
    for worker in numba.prange(workers):
        compiled.take(arrived, 1)
        for _ in range(10**9):  # wait (a while at most) for the other workers: all take at once
            if compiled.take(arrived, 0) >= workers:
                break
        while True:
            first = compiled.take(taken, grain)
            if first >= jobs:
                break
            for j in range(first, min(jobs, first + grain)):
                times[worker, j] += 1
    return times


_TWO_CORES = pytest.mark.skipif(
    numba.config.NUMBA_NUM_THREADS < 2, reason="needs two threads to share the work"
)


@_TWO_CORES
@pytest.mark.parametrize("grain", [1, 7])
def test_cores_taking_jobs_from_one_counter_take_each_job_exactly_once(grain):
    # with a plain add for take, both workers took every job (measured)
    assert (_times_taken(1_000_000, grain, 2).sum(axis=0) == 1).all()


@_TWO_CORES
def test_the_image_does_not_depend_on_which_core_takes_which_tile():
    scenes = [_packet_scenes()["classic_lit_at_1e6"], _crowd(np.random.default_rng(11), 200)]
    mirrors = load_scene(SCENES / "mirror_balls.json")
    scenes.append(replace(mirrors, camera=replace(mirrors.camera, width=80, height=60)))
    threads = numba.get_num_threads()
    try:
        for scene in scenes:
            prepared = compiled.prepare(scene)
            numba.set_num_threads(1)
            rgb, index, t = compiled.render(prepared, 2)
            numba.set_num_threads(threads)
            for progress in (None, lambda rows: None) * 3:  # one call, or one per band of rows
                again = compiled.render(prepared, 2, progress=progress)
                assert np.array_equal(again[1], index)
                _exactly(again[2], t)
                _exactly(again[0], rgb)
    finally:
        numba.set_num_threads(threads)


def _ties_reversed(tiles):
    """The same tiles, with each tile's objects at the same closest t listed higher index
    first: the answer must not depend on it (a tie keeps the lower index, whatever the order)."""
    objects, entries = tiles.objects.copy(), tiles.entries.copy()
    for k in range(len(tiles.start) - 1):
        span = slice(tiles.start[k], tiles.start[k + 1])
        order = np.lexsort((-objects[span], entries[span, 4]))
        objects[span], entries[span] = objects[span][order], entries[span][order]
    return tiles._replace(objects=objects, entries=entries)


def test_every_kind_of_scene_hands_the_kernels_arrays_of_one_kind():
    # numba compiles the kernels again (minutes) for each new kind of array, read-only included
    plain = {
        "camera": {"eye": [0, 0, 6], "lookat": [0, 0, 0], "up": [0, 1, 0], "fov_angle": 50,
                   "width": 32, "height": 24},
        "spheres": [{"center": [x, 0, 0], "radius": 0.5, "color": [1, 0, 0]} for x in (-1, 1)],
    }  # fmt: skip
    scenes = {
        "named spheres, textures": load_scene(SCENES / "classic.json"),
        "lights, mirrors": load_scene(SCENES / "mirror_balls.json"),
        "plain spheres, kept as read-only columns": scene_from_dict(plain),
        "billboards only": replace(load_scene(SCENES / "cutouts.json"), spheres=()),
        "crowd": _crowd(np.random.default_rng(5), 50),
    }
    kinds = {name: numba.typeof(compiled.prepare(scene)[1:]) for name, scene in scenes.items()}
    assert len(set(kinds.values())) == 1, kinds


@contextlib.contextmanager
def arguments_typed_in_python():
    """The names of the kernels whose arguments numba types in Python (its slow path) while in
    the block. Numba's dispatcher finds the compiled code for a call by a fingerprint of its
    arguments' types, in C; an argument it cannot fingerprint, or one whose fingerprint another
    class took first (a NamedTuple of the same name and fields), is typed in Python on every
    call."""
    from numba.core.dispatcher import _DispatcherBase

    typed = []
    typeof_pyval = _DispatcherBase.typeof_pyval

    def counted(dispatcher, value):
        typed.append(dispatcher.py_func.__name__)
        return typeof_pyval(dispatcher, value)

    _DispatcherBase.typeof_pyval = counted
    try:
        yield typed
    finally:
        _DispatcherBase.typeof_pyval = typeof_pyval


def test_numba_types_in_python_a_namedtuple_whose_name_and_fields_another_class_took():
    # why the benchmark of the engine before and after (benchmarks/compile_time.py) runs
    # each engine in a process of its own, and the control for the test below
    from typing import NamedTuple

    class Pair(NamedTuple):
        a: float
        b: float

    first = Pair

    class Pair(NamedTuple):  # noqa: F811 (the point: a second class of the same name)
        a: float
        b: float

    def total(pair):
        return pair.a + pair.b

    # each class to a kernel of its own, as each engine passes its own to its own kernels
    total_of_first, total_of_second = numba.njit(total), numba.njit(total)
    total_of_first(first(1.0, 2.0))
    total_of_second(Pair(1.0, 2.0))
    with arguments_typed_in_python() as typed:
        assert total_of_first(first(1.0, 2.0)) == 3.0
    assert typed == []
    with arguments_typed_in_python() as typed:
        assert total_of_second(Pair(1.0, 2.0)) == 3.0
    assert typed == ["total"]


@pytest.mark.parametrize("name", ["classic.json", "shadow_on_billboard.json"])
def test_a_prepared_render_finds_its_kernels_without_typing_an_argument_in_python(name):
    prepared = compiled.prepare(load_scene(SCENES / name))
    compiled.render(prepared)  # loads the kernels (their first call types its arguments)
    with arguments_typed_in_python() as typed:
        compiled.render(prepared)
    assert typed == []


def test_tile_side_sends_rays_in_packets_unless_the_picture_is_crowded():
    classic = load_scene(SCENES / "classic.json")
    assert compiled.prepare(classic).tiles[-2:] == (compiled.WIDE_SIDE, True)
    width = height = 64
    rng = np.random.default_rng(3)
    corners = rng.uniform(0, 48, size=(800, 2))  # 800 squares 16 pixels wide on 64 x 64
    bounds = np.column_stack([corners[:, 0], corners[:, 0] + 16, corners[:, 1], corners[:, 1] + 16])
    assert compiled.tile_side(bounds, width, height) == (compiled.CROWDED_SIDE, False)
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


# ---- the engine choice -----------------------------------------------------------------------


def test_auto_keeps_small_renders_on_numpy_and_an_unknown_engine_is_refused():
    scene = load_scene(SCENES / "classic.json")
    assert choice.choose("auto", scene) == "numpy"  # numba's load would cost more than it saves
    assert choice.choose("compiled", scene) == "compiled"
    with pytest.raises(ValueError, match="engine must be one of auto, numpy, compiled"):
        render(scene, engine="fast")
    with pytest.raises(ValueError, match="float64 only"):
        render(scene, engine="compiled", dtype=np.float32)


def test_auto_takes_the_compiled_engine_for_large_work_once_it_is_compiled(monkeypatch):
    scene = load_scene(SCENES / "classic.json")
    big = replace(scene, camera=replace(scene.camera, width=1920, height=1080))
    monkeypatch.setattr(choice, "compiled_once", lambda entry: entry == "trace_flat")
    assert choice.choose("auto", big, samples=3) == "compiled"
    assert choice.choose("auto", big, samples=3, dtype=np.float32) == "numpy"
    lit = load_scene(SCENES / "classic_lit.json")
    lit = replace(lit, camera=replace(lit.camera, width=1920, height=1080))
    assert choice.choose("auto", lit, samples=3) == "numpy"  # its kernels are not compiled yet
    monkeypatch.setattr(choice, "compiled_once", lambda entry: False)  # a first compile costs more
    assert choice.choose("auto", big, samples=3) == "numpy"


def _run(code, cwd=REPO, **env):
    return subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=cwd,
        env={**os.environ, **env},
        timeout=600,
    )


def test_cli_refuses_the_compiled_engine_without_numba_in_one_line_naming_the_fix(tmp_path):
    out = tmp_path / "out.png"
    code = (
        "import sys, importlib.util as u\n"
        "find = u.find_spec\n"
        "u.find_spec = lambda name, *a: None if name == 'numba' else find(name, *a)\n"
        "from raykit.cli import main\n"
        f"sys.exit(main(['render', 'scenes/classic.json', '-o', {str(out)!r}, "
        "'--engine', 'compiled']))"
    )
    run = _run(code)
    assert run.returncode == 2
    assert run.stderr.strip().splitlines() == [
        "raykit: error: --engine compiled needs numba, which is not installed: "
        'pip install "raykit[fast]"'
    ]
    assert not out.exists()
    unknown = _run(
        "import sys; from raykit.cli import main; "
        f"sys.exit(main(['render', 'scenes/classic.json', '-o', {str(out)!r}, '--engine', 'gpu']))"
    )
    assert unknown.returncode == 2 and "invalid choice: 'gpu'" in unknown.stderr


def test_small_renders_never_import_numba():
    run = _run(
        "import sys\n"
        "from raykit.io.scene_json import load_scene\n"
        "from raykit.render import render\n"
        "render(load_scene('scenes/classic.json'))\n"
        "assert 'numba' not in sys.modules, 'numba was imported'\n"
    )
    assert run.returncode == 0, run.stderr


def test_cache_folder_is_keyed_on_the_engines_source(tmp_path, monkeypatch):
    import shutil

    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path))
    shutil.copytree(REPO / "raykit", tmp_path / "raykit", ignore=shutil.ignore_patterns("__py*"))
    package = tmp_path / "raykit/engine/compiled"
    monkeypatch.setattr(choice, "COMPILED_SOURCE", package)
    before = choice.cache_folder()
    source = package / "spheres.py"  # a kernel that the others call
    text = source.read_text()
    edited = text.replace("if not discriminant >= 0:", "if not discriminant >= 9:")
    assert edited != text
    source.write_text(edited)
    assert choice.cache_folder() != before
    assert choice.cache_folder().parent == before.parent == tmp_path / "raykit"


def test_a_second_copy_of_the_same_source_gets_its_own_cache_folder(tmp_path, monkeypatch):
    # numba keeps each source folder's kernels apart, so a second copy (another checkout, a
    # reinstall elsewhere) compiles again: it must say so, and auto must not count on a cache
    import shutil

    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    one, two = (tmp_path / copy / "raykit/engine/compiled" for copy in ("one", "two"))
    for package in (one, two):
        shutil.copytree(REPO / "raykit", package.parent.parent,
                        ignore=shutil.ignore_patterns("__py*"))  # fmt: skip
    monkeypatch.setattr(choice, "COMPILED_SOURCE", one)
    first = choice.cache_folder()
    choice.marker("trace_flat").write_text("20.0 s\n")  # as the first copy's first render leaves it
    assert choice.compiled_once("trace_flat")
    monkeypatch.setattr(choice, "COMPILED_SOURCE", two)
    assert choice.cache_folder() != first
    assert not choice.compiled_once("trace_flat")


@pytest.fixture
def fake_compile(monkeypatch):
    """The compile clock's module, with a clock that stands still (``now[0]``, seconds: move it
    by hand), and ``event(name)``, a numba compile event of one of the package's kernels."""
    from types import SimpleNamespace

    from raykit.engine.compiled import compiling

    now = [100.0]
    monkeypatch.setattr(compiling.time, "perf_counter", lambda: now[0])

    def event(name):
        kernel = SimpleNamespace(__name__=name, __module__="raykit.engine.compiled.driver")
        return SimpleNamespace(data={"dispatcher": SimpleNamespace(py_func=kernel)})

    return compiling, now, event


def test_the_progress_line_counts_a_kernel_as_it_compiles_up_to_its_measured_seconds(
    fake_compile,
):
    """The line moves while a long kernel compiles, never past the kernel's measured seconds
    before it ends, and the whole table once every kernel has ended."""
    compiling, now, event = fake_compile
    clock = compiling.CompileClock("trace_lit", show=False)
    clock.expected = {"lit_job": 20.0, "light_lanes": 6.0}
    clock.on_start(event("lit_job"))
    now[0] += 3.0
    assert clock.progress(now[0]) == 3.0  # lit_job's own seconds so far
    clock.on_start(event("light_lanes"))
    now[0] += 2.0
    assert clock.progress(now[0]) == 3.0 + 2.0  # lit_job's 3 s are kept, and light_lanes' 2 s
    now[0] += 10.0
    assert clock.progress(now[0]) == 3.0 + 6.0  # up to its measured 6 s, however slow this is
    clock.on_end(event("light_lanes"))
    assert clock.progress(now[0]) == 6.0 + 3.0  # lit_job's own 3 s, not the 12 s in its callee
    now[0] += 30.0
    assert clock.progress(now[0]) == 6.0 + 20.0
    clock.on_end(event("lit_job"))
    assert clock.progress(now[0]) == 26.0
    assert clock.own == {"light_lanes": 12.0, "lit_job": 33.0}


def test_the_line_ends_full_when_some_of_the_tables_kernels_came_from_the_cache(
    fake_compile, monkeypatch, capsys
):
    compiling, now, event = fake_compile
    monkeypatch.setattr(compiling, "measured_seconds", lambda: {"trace_mirrors": {
        "mirror_rays": 7.0, "light_lanes": 4.0}})  # fmt: skip
    clock = compiling.CompileClock("trace_mirrors", show=True)
    clock.on_start(event("mirror_rays"))  # light_lanes is cached (trace_lit compiled it)
    now[0] += 7.0
    clock.on_end(event("mirror_rays"))
    assert clock.bar.n == 7.0
    clock.finish()
    assert clock.bar.n == clock.bar.total == 11.0
    clock.bar.close()
    assert "100%" in capsys.readouterr().err


def test_the_time_left_starts_at_the_tables_seconds_and_follows_this_machines_pace(
    fake_compile, monkeypatch
):
    compiling, now, event = fake_compile
    monkeypatch.setattr(compiling, "PRIOR_SECONDS", 5.0)
    clock = compiling.CompileClock("trace_lit", show=False)
    clock.expected = {"bin_by_tile": 1.0, "lit_job": 29.0}
    clock.on_start(event("bin_by_tile"))
    assert clock.seconds_left(now[0]) == 30.0  # nothing known yet of this machine: the table's
    now[0] += 4.0  # the first kernel takes longer than the table's 1 s (numba warms up)
    # the pace alone, 4 s for 1 s done, would say 29 x 4 = 116 s left
    assert clock.seconds_left(now[0]) == 29.0 * (4.0 + 5.0) / (1.0 + 5.0)
    clock.on_end(event("bin_by_tile"))
    clock.on_start(event("lit_job"))
    now[0] += 10.0
    assert clock.seconds_left(now[0]) == 19.0 * (14.0 + 5.0) / (11.0 + 5.0)
    now[0] += 19.0
    clock.on_end(event("lit_job"))
    assert clock.seconds_left(now[0]) == 0.0


def _callback_interrupted_by_ctrl_c():
    """A call from C into Python that a Ctrl-C interrupts, as llvmlite's object-cache callback
    was as LLVM finished a kernel: ctypes reports the KeyboardInterrupt to sys.unraisablehook
    and returns as if nothing happened."""
    import ctypes

    @ctypes.CFUNCTYPE(None)
    def callback():
        raise KeyboardInterrupt

    callback()


def test_a_ctrl_c_swallowed_by_a_callback_from_llvm_stops_the_compile_at_the_next_kernel():
    from raykit.engine.compiled.compiling import compile_clock

    @numba.njit(cache=False)
    def next_kernel(x):
        return x + 1

    hook = sys.unraisablehook
    with pytest.raises(KeyboardInterrupt):
        with compile_clock("trace_flat", show=False) as clock:
            _callback_interrupted_by_ctrl_c()
            assert clock.interrupted  # swallowed, and noted
            next_kernel(1)
    assert not next_kernel.signatures  # stopped as its compile started
    assert sys.unraisablehook is hook


def test_a_ctrl_c_swallowed_in_the_last_kernel_is_raised_as_the_call_returns():
    from raykit.engine.compiled.compiling import compile_clock

    with pytest.raises(KeyboardInterrupt):
        with compile_clock("trace_flat", show=False):
            _callback_interrupted_by_ctrl_c()


def test_any_other_error_a_callback_swallows_goes_to_the_hook_that_was_there(monkeypatch):
    import ctypes

    from raykit.engine.compiled.compiling import compile_clock

    reported = []
    monkeypatch.setattr(sys, "unraisablehook", lambda report: reported.append(report.exc_value))

    @ctypes.CFUNCTYPE(None)
    def callback():
        raise ValueError("not a Ctrl-C")

    with compile_clock("trace_flat", show=False) as clock:
        callback()
    assert not clock.interrupted
    assert [str(error) for error in reported] == ["not a Ctrl-C"]


def test_an_edited_kernel_is_compiled_again_not_served_from_the_cache(tmp_path):
    """The edit keeps the file's size and time, which numba's own cache check would miss."""
    import shutil

    shutil.copytree(REPO / "raykit", tmp_path / "raykit", ignore=shutil.ignore_patterns("__py*"))
    kernel = tmp_path / "raykit/engine/compiled/spheres.py"
    code = (
        "from raykit.io.scene_json import load_scene; from raykit.render import render\n"
        f"scene = load_scene({str(SCENES / 'classic.json')!r})\n"
        "print((render(scene, engine='compiled').object_index >= 0).sum())\n"
    )
    env = {"PYTHONPATH": str(tmp_path), "RAYKIT_CACHE_DIR": str(tmp_path / "cache")}
    first = _run(code, cwd=tmp_path, **env)
    assert first.returncode == 0, first.stderr
    assert "compiling raykit's fast kernels, once" in first.stderr
    # the progress line names the kernels it compiles: a flat scene's, and no shading
    assert "trace_flat" in first.stderr and "light_lanes" not in first.stderr
    again = _run(code, cwd=tmp_path, **env)
    assert "compiling" not in again.stderr and again.stdout == first.stdout  # served cached
    stat = kernel.stat()
    text = kernel.read_text()
    edited = text.replace("if not discriminant >= 0:", "if not discriminant >= 9:")
    assert edited != text and len(edited) == len(text)
    kernel.write_text(edited)
    os.utime(kernel, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    third = _run(code, cwd=tmp_path, **env)
    assert "compiling raykit's fast kernels, once" in third.stderr
    assert int(third.stdout) < int(first.stdout)  # the edit shows: fewer spheres are hit


def test_a_lit_scene_without_mirrors_never_types_the_mirror_rays():
    """A scene compiles only what it uses: a lit scene with no mirror passes lit_job ``bounces``
    None, and numba's pruning of branches on argument types, run before typing, drops the call
    of mirror_rays (so it is never typed, compiled or linked); a scene with mirrors keeps it, and
    its entry point is named apart (its own marker and progress line), as
    :func:`raykit.engine.choice.entry_point` names it. (Checked on the IR: which kernels a
    process compiles depends on what its cache already holds.)"""
    import inspect

    from numba.core import ir, types
    from numba.core.analysis import dead_branch_prune
    from numba.core.compiler import run_frontend

    from raykit.engine.compiled import driver
    from raykit.engine.compiled import shading as kernels

    parameters = list(inspect.signature(driver.lit_job.py_func).parameters)

    def calls_mirror_rays(bounces) -> bool:
        kind = types.none if bounces is None else types.boolean
        lit_job = run_frontend(driver.lit_job.py_func)
        dead_branch_prune(lit_job, tuple(kind if p == "bounces" else types.pyobject
                                         for p in parameters))  # fmt: skip
        return any(
            isinstance(statement.value, ir.Global) and statement.value.value is kernels.mirror_rays
            for block in lit_job.blocks.values()
            for statement in block.find_insts(ir.Assign)
        )

    seen = []
    for name in ("classic", "classic_lit", "mirror_balls"):
        scene = load_scene(SCENES / f"{name}.json")
        entry, _, leading = driver._entry(compiled.prepare(scene))
        seen.append((entry, calls_mirror_rays(leading[-1]) if entry != "trace_flat" else None))
    assert seen == [("trace_flat", None), ("trace_lit", False), ("trace_mirrors", True)]


def test_ctrl_c_during_the_first_compile_leaves_a_cache_the_next_run_renders_right_from(tmp_path):
    """numba writes each kernel's cache files whole; the marker comes only after a render."""
    import signal
    import threading
    import time

    from raykit.engine.compiled.compiling import MESSAGE

    code = (
        "from raykit.io.scene_json import load_scene; from raykit.render import render\n"
        f"scene = load_scene({str(SCENES / 'classic.json')!r})\n"
        "print((render(scene, engine='compiled').object_index >= 0).sum())\n"
    )
    cache = tmp_path / "cache"
    env = {**os.environ, "RAYKIT_CACHE_DIR": str(cache)}
    # Ctrl-C as in a terminal: a child started where SIGINT is ignored (a shell's background
    # job) would inherit that, and finish its compile
    child = subprocess.Popen(
        [sys.executable, "-c", code], cwd=REPO, env=env, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    said = []  # its standard error, read as it comes (the progress line)
    reader = threading.Thread(target=lambda: said.extend(iter(child.stderr.readline, "")))
    reader.start()
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and not (
        list(cache.rglob("*.nbi")) and MESSAGE in "".join(said)  # a kernel cached, and the
    ):  # progress line up: the entry point's compile is under way
        time.sleep(0.05)
    child.send_signal(signal.SIGINT)
    stdout = child.stdout.read()
    child.wait(timeout=300)
    reader.join()
    stderr = "".join(said)
    assert child.returncode != 0, f"the compile finished before it was interrupted: {stdout}"
    assert "KeyboardInterrupt" in stderr, (child.returncode, stdout, stderr[-2000:])
    assert list(cache.rglob("*.nbi")) and not list(cache.rglob("*.ok"))
    again = _run(code, RAYKIT_CACHE_DIR=str(cache))
    assert again.returncode == 0, again.stderr
    assert "compiling raykit's fast kernels, once" in again.stderr  # what was not cached
    expected = (render(load_scene(SCENES / "classic.json")).object_index >= 0).sum()
    assert int(again.stdout) == expected
    assert [path.name for path in cache.rglob("*.ok")] == ["trace_flat.ok"]


def test_a_wrong_submission_still_renders_wrong_with_numba_installed(tmp_path, child_python):
    """The grader runs the student's own numpy functions: the compiled engine never stands in."""
    from mistaken_submissions import make_submission
    from raykit_grading.grade import Options, grade

    submission = make_submission(tmp_path, "rows_flipped")
    assert (submission / "raykit/engine/compiled/spheres.py").exists()  # even with it there
    results = grade(submission, options=Options(child_python), names=["3.6"])
    (test,) = results["tests"]
    assert test["score"] == 0, test


def test_the_starter_kit_ships_no_compiled_engine(tmp_path):
    from raykit_grading.release import build_release

    build_release(tmp_path / "kit")
    assert not (tmp_path / "kit/raykit/engine/compiled").exists()
    assert (tmp_path / "kit/raykit/engine/choice.py").exists()


# the kinds of scene the example scenes and the crowds above never render, and the first eight
# scenes random_scene makes from seed 26 all have between them (with an adaptive render): one
# image 1 pixel wide or so, a 1 or 179 degree view, the camera in a sphere, a billboard edge-on
# to the eye, lights in and on objects, mirrors with no light, 1,500 objects, tiny spheres...
KINDS_NEVER_RENDERED_ELSEWHERE = {
    "odd image size (1x1, 1x37, 97x3, ...)",
    "fov_angle 1, 2.5, 160 or 179 degrees",
    "camera inside a sphere",
    "billboard edge-on to the eye",
    "point light on a surface",
    "point light inside an object",
    "materials, no lights nor ambient",
    "401 to 1,500 objects",
    "tiny spheres on pixels' rays (radius 1e-5 to 1e-4)",
    "object behind the camera",
    "mirrors, max_depth 4",
}


def test_random_scenes_of_every_kind_render_the_same_with_both_engines(tmp_path):
    from random_scenes import make_textures, random_scene

    rng = np.random.default_rng(26)
    textures = make_textures(rng, tmp_path / "textures")
    kinds, adaptive = set(), False
    for _ in range(8):
        data, options, tags = random_scene(rng, textures)
        kinds |= tags
        adaptive |= options["adaptive"]
        _same_render(scene_from_dict(data, folder=tmp_path), **options)
    assert KINDS_NEVER_RENDERED_ELSEWHERE <= kinds and adaptive

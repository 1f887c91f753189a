"""The shading kernels (raykit.engine.compiled.shading) against raykit.shading: one ray, and a
job's rays in lanes."""

from __future__ import annotations

from dataclasses import replace

import numba
import numpy as np
import pytest
from libm_power import libm_power

from conftest import shifted_scene
from raykit import shading
from raykit.engine import compiled
from raykit.engine.compiled import shading as kernels
from raykit.engine.noise import Dimensions
from raykit.lights import AreaLight, DirectionalLight, PointLight
from raykit.rays import dot, normalize
from raykit.render import cast, secondary_caster

from .harness import (
    EPS,
    RAYS,
    exactly,
    lit_crowd,
    rays_into_crowd,
    same_render,
    twin_test,
)


@numba.njit
def _shade(arrays, tree, shading, origins, directions, index, t, color, uniforms=None):
    """compiled.shade of each ray, with its row of a distributed sample's ``uniforms (N, D)``
    (None: no row, the area lights' centres)."""
    out = np.empty((len(origins), 3))
    stack = compiled.new_stack()
    none = np.empty(0)
    scene = compiled.CompiledScene(arrays, tree, shading)
    for i in range(len(origins)):
        o, d, c = origins[i], directions[i], color[i]
        numbers = none if uniforms is None else np.ascontiguousarray(uniforms[i])
        nearest = compiled.NearestHit(index[i], t[i], c[0], c[1], c[2])
        out[i, 0], out[i, 1], out[i, 2] = compiled.shade(
            scene, stack, (o[0], o[1], o[2]), (d[0], d[1], d[2]), nearest, numbers
        )
    return out


def test_shading_kernel_repeats_shade_bit_for_bit_with_the_same_pow():
    rng = np.random.default_rng(45)
    scene = lit_crowd(rng, 40)
    origins, directions = rays_into_crowd(rng, RAYS)
    hits = cast(scene, origins, directions)
    with libm_power():
        expected = shading.shade(scene, secondary_caster(scene), origins, directions, hits)
    got = _shade(
        compiled.scene_arrays(scene), compiled.scene_tree(scene), compiled.scene_shading(scene),
        origins, directions, hits.index, hits.t, hits.color,
    )  # fmt: skip
    exactly(got, expected)
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
    none = np.empty(0)  # no sample's uniform numbers: no area light to sample
    scene = compiled.CompiledScene(arrays, tree, shading)
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
        compiled.light_lanes(scene, stack, rays, best, count, lanes, candidates, counts[tile],
                             np.empty((0, 0)))  # fmt: skip
        for i in range(count):
            in_lanes[tile, i] = lane_total[:, i]
            one_by_one[tile, i, 0], one_by_one[tile, i, 1], one_by_one[tile, i, 2] = \
                compiled.surface_color(
                    scene, stack, 0, (p[tile, i, 0], p[tile, i, 1], p[tile, i, 2]),
                    (n[tile, i, 0], n[tile, i, 1], n[tile, i, 2]),
                    (d[tile, i, 0], d[tile, i, 1], d[tile, i, 2]), error[tile, i],
                    (0.5, 0.5, 0.5), none, 0,
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
            l = -normalize(light.direction)  # FOCG's l, toward the light
            across = normalize(np.cross(l, rng.normal(size=3)))
            tangent = sphere.center + sphere.radius * across
            start = tangent - l * rng.uniform(0.1, 5)
        jitter = rng.normal(size=(count, 3)) * 10 ** rng.uniform(-12, -3)
        jitter[0] = 0.0  # one exactly grazing
        p[k] = start + jitter
    return p


@pytest.mark.parametrize("offset", [0.0, 1e6])
@pytest.mark.parametrize("crowd", [40, 80])  # 54 objects, each tested for the lists; 104: a tree
def test_shading_in_lanes_gives_every_surface_point_the_colour_surface_color_gives(crowd, offset):
    rng = np.random.default_rng(77 + crowd)
    people = lit_crowd(rng, crowd)
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
    exactly(listed, one_by_one)
    # the lists were used, and the shadows they decide differ from point to point
    assert (counts >= 0).mean() > 0.5 and (counts == -1).any()
    walked, _, _ = _in_lanes_and_one_by_one(arrays, tree, shading, p, n, d, error, False)
    exactly(walked, one_by_one)
    unshadowed = shading._replace(shadows=False)
    lit, _, _ = _in_lanes_and_one_by_one(arrays, tree, unshadowed, p, n, d, error, True)
    in_shadow = (lit != one_by_one).any(axis=2)
    assert 0.05 < in_shadow.mean() < 0.95


@pytest.mark.parametrize("samples", [1, 2])
@pytest.mark.parametrize("offset", [0.0, 1e6])
def test_lit_crowds_with_awkward_lights_render_the_same_with_both_engines(samples, offset):
    rng = np.random.default_rng(int(samples + offset % 97))
    crowd = lit_crowd(rng, 30)
    scene = shifted_scene(replace(crowd, lights=_awkward_lights(rng, crowd)), [offset] * 3)
    same_render(scene, samples=samples)


def _lambert(rng):
    count = 4000
    kd = rng.uniform(size=(count, 3))
    n, l = normalize(rng.normal(size=(2, count, 3)))  # FOCG's n and l
    intensity = rng.uniform(size=3)
    n_dot_l = dot(n, l)
    got = [kernels.lambert(tuple(kd[i]), tuple(intensity), n_dot_l[i]) for i in range(count)]
    exactly(got, shading.lambert(kd, intensity, n, l))


def _blinn_phong(rng):
    count = 4000
    ks, n, l, v = rng.uniform(size=(count, 3)), *normalize(rng.normal(size=(3, count, 3)))
    intensity, p = rng.uniform(size=3), rng.choice([1.0, 8.0, 32.0, 100.0], size=count)
    got = [
        kernels.blinn_phong(tuple(ks[i]), tuple(intensity), tuple(n[i]), tuple(l[i]), tuple(v[i]),
                            p[i])
        for i in range(count)
    ]  # fmt: skip
    with libm_power():  # the one operation that differs: the pow (raykit.engine.compiled)
        exactly(got, shading.blinn_phong(ks, intensity, n, l, v, p))


def _shade_checked(rng, max_depth):
    scene = replace(lit_crowd(rng, 30), max_depth=max_depth)
    origins, directions = rays_into_crowd(rng, 5000)
    hits = cast(scene, origins, directions)
    with libm_power():
        expected = shading.shade(scene, secondary_caster(scene), origins, directions, hits)
    got = _shade(compiled.scene_arrays(scene), compiled.scene_tree(scene),
                 compiled.scene_shading(scene), origins, directions, hits.index, hits.t,
                 hits.color)  # fmt: skip
    exactly(got, expected)


def _with_area_lights(rng, scene):
    """``scene`` with three area lights among its lights (one large, one small and far, both
    FOCG's, and a physically based one lighting the crowd from one side, its back the
    other's)."""
    lights = (
        AreaLight(np.array([-2.0, 7.0, 6.0]), np.array([4.0, 0, 0]), np.array([0, 0.5, 3.0]),
                  np.array([0.6, 0.6, 0.5])),
        *scene.lights,
        AreaLight(rng.normal(size=3) * 3 + [0, 0, 12], rng.normal(size=3) * 0.1,
                  rng.normal(size=3) * 0.1, np.array([0.3, 0.2, 0.4])),
        AreaLight(np.array([-3.0, 1.0, 0.0]), np.array([0, 2.0, 0]), np.array([0, 0, 2.0]),
                  np.array([2.0, 1.8, 1.5]), physical=True),
    )  # fmt: skip
    return replace(scene, lights=lights)


def _glossy(rng, scene):
    """``scene`` with every other mirror glossy."""
    mirrors = [k for k, s in enumerate(scene.spheres) if s.material.is_mirror][::2]
    spheres = list(scene.spheres)
    for k in mirrors:
        material = replace(spheres[k].material, glossiness=float(rng.uniform(0.05, 0.6)))
        spheres[k] = replace(spheres[k], material=material)
    return replace(scene, spheres=tuple(spheres))


def _shade_sampled(rng, max_depth, uniforms=True):
    """shade with area lights and glossy mirrors, each ray's points on the lights and its
    perturbations from its row of uniform numbers (or, ``uniforms`` False, the lights' centres
    and ideal reflections), at every mirror depth."""
    scene = _glossy(rng, _with_area_lights(rng, lit_crowd(rng, 30)))
    scene = replace(scene, max_depth=max_depth)
    origins, directions = rays_into_crowd(rng, 5000)
    hits = cast(scene, origins, directions)
    dimensions = Dimensions.of(scene)
    assert dimensions.glossy == (max_depth > 0)
    numbers = rng.uniform(size=(len(origins), dimensions.count)) if uniforms else None
    on_lights = gloss = None
    if uniforms:
        shape = (len(origins), max_depth + 1, scene.area_lights, 2)
        lights = slice(dimensions.light(0, 0), dimensions.light(max_depth + 1, 0))
        on_lights = numbers[:, lights].reshape(shape)
        if dimensions.glossy:
            glossy = slice(dimensions.gloss(0), dimensions.gloss(max_depth))
            gloss = numbers[:, glossy].reshape(len(origins), max_depth, 2)
    with libm_power():
        expected = shading.shade(scene, secondary_caster(scene), origins, directions, hits,
                                 on_lights, gloss_uniforms=gloss)  # fmt: skip
    got = _shade(compiled.scene_arrays(scene), compiled.scene_tree(scene),
                 compiled.scene_shading(scene), origins, directions, hits.index, hits.t,
                 hits.color, numbers)  # fmt: skip
    exactly(got, expected)


@pytest.mark.parametrize("uniforms", [True, False])
def test_area_lights_and_glossy_mirrors_shade_the_same_with_both_engines_at_every_depth(uniforms):
    _shade_sampled(np.random.default_rng(46), 3, uniforms)


def _in_lanes(rng):  # a job's rays in lanes, mirrors after: a render, to the bit
    scene = lit_crowd(rng, 30)
    same_render(replace(scene, camera=replace(scene.camera, width=40, height=30)))


CHECKS = {
    "shading.lambert": _lambert,
    "shading.blinn_phong": _blinn_phong,
    "shading.surface_color": lambda rng: (_shade_checked(rng, 0), _shade_sampled(rng, 0)),
    "shading.shade": lambda rng: _shade_checked(rng, 3),
    "shading.bounce_on": lambda rng: (_shade_checked(rng, 3), _shade_sampled(rng, 2)),
    "shading.surface_lanes": _in_lanes,
    "shading.light_lanes": _in_lanes,
    "shading.mirror_rays": _in_lanes,
}
test_the_twin_repeats_its_reference = twin_test("shading", CHECKS)

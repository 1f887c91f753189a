"""The bounding volume hierarchy answers exactly what brute force answers, and skips work."""

import json

import numpy as np
import pytest

import raykit.engine.regions
import raykit.render
from conftest import SCENES, random_scene, scene_dict, write_texture
from raykit.engine.arrays import SceneArrays
from raykit.engine.boxes import objects_near_segments
from raykit.engine.bvh import BVH
from raykit.engine.regions import cast_nearby
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.render import cast, render


def _random_rays(rng, count, spread=6.0):
    origins = rng.uniform(-spread, spread, (count, 3))
    directions = rng.normal(size=(count, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return origins, directions


def _axis_rays():
    """Rays along the axes from points on box faces: the slab test's 0 x inf corner."""
    origins = np.array([[0, 0, 0], [-6, 0, 0], [0, 0, -6], [0.5, 1, 2]], float).repeat(6, 0)
    directions = np.tile(np.vstack([np.eye(3), -np.eye(3)]), (4, 1))
    return origins, directions


def _same_hits(scene, origins, directions):
    want = cast(scene, origins, directions)
    got = BVH.build(scene).cast(origins, directions)
    assert np.array_equal(got.index, want.index)
    assert np.array_equal(got.t, want.t)
    assert np.array_equal(got.color, want.color)
    return want


@pytest.mark.parametrize("name", ["classic", "cutouts", "orthographic", "wide_fov"])
def test_bvh_hits_equal_brute_force_on_the_example_scenes(name):
    scene = load_scene(SCENES / f"{name}.json")
    hits = _same_hits(scene, *_random_rays(np.random.default_rng(7), 20000))
    assert 0.1 < np.mean(hits.index >= 0) < 0.9
    _same_hits(scene, *_axis_rays())


def test_bvh_hits_equal_brute_force_on_random_scenes(tmp_path):
    rng = np.random.default_rng(11)
    write_texture(tmp_path, "noise.png", rng.integers(0, 256, (5, 7, 4)))
    for _ in range(20):
        scene = scene_from_dict(random_scene(rng, "noise.png"), folder=tmp_path)
        _same_hits(scene, *_random_rays(rng, 3000))


def _many_spheres(count, seed=3):
    rng = np.random.default_rng(seed)
    centers, radii = rng.uniform(-10, 10, (count, 3)), rng.uniform(0.1, 0.5, count)
    spheres = [
        {"center": c.tolist(), "radius": float(r), "color": [0.5, 0.5, 0.5]}
        for c, r in zip(centers, radii, strict=True)
    ]
    return scene_from_dict(scene_dict(spheres=spheres))


def test_bvh_tests_few_objects_per_ray_in_a_big_scene():
    scene = _many_spheres(2000)
    bvh = BVH.build(scene)
    origins, directions = _random_rays(np.random.default_rng(5), 2000, spread=10)
    rays, objects = bvh.candidates(origins, directions)
    assert len(rays) / len(origins) < 0.05 * len(scene.objects)  # brute force tests all
    _same_hits(scene, origins, directions)


def test_empty_scene_has_an_empty_bvh():
    scene = scene_from_dict({"camera": json.loads((SCENES / "classic.json").read_text())["camera"]})
    hits = BVH.build(scene).cast(*_random_rays(np.random.default_rng(1), 10))
    assert np.all(hits.index == -1)


def test_shaded_render_is_the_same_through_the_bvh_and_by_brute_force(monkeypatch):
    data = json.loads((SCENES / "classic_lit.json").read_text())
    data["camera"].update(width=120, height=90)
    data["spheres"][0]["mirror"] = [0.6, 0.6, 0.6]
    scene = scene_from_dict(data, folder=SCENES)

    def every_object(s, cast_scene, arrays=None):
        return lambda origins, directions, t_max=None: cast_scene(s, origins, directions)

    monkeypatch.setattr(raykit.engine.regions, "secondary_caster", every_object)
    brute = render(scene)
    monkeypatch.setattr(
        raykit.engine.regions, "secondary_caster", lambda s, c, a=None: BVH.build(s, a).cast
    )
    through_bvh = render(scene)
    assert np.array_equal(brute.rgb, through_bvh.rgb)


def _shadow_bundles(rng):
    """A tile's shadow rays, from points close together: toward a point light (up to it) and
    toward a directional light (t_max inf)."""
    origins = rng.uniform(-4, 4, 3) + 0.3 * rng.normal(size=(500, 3))
    to_light = rng.uniform(-4, 4, 3) - origins
    distance = np.linalg.norm(to_light, axis=1)
    yield origins, to_light / distance[:, None], distance
    sun = rng.normal(size=3)
    sun /= np.linalg.norm(sun)
    yield origins, np.tile(sun, (500, 1)), np.full(500, np.inf)


def test_segments_reach_every_object_they_hit_and_skip_the_rest(tmp_path):
    """Culling by segment boxes is conservative: whatever a segment o + [0, t_max]·d hits is
    kept, so cast_nearby and the BVH with t_max agree with cast on every hit before t_max."""
    rng = np.random.default_rng(21)
    write_texture(tmp_path, "noise.png", rng.integers(0, 256, (5, 7, 4)))
    skipped = 0
    for _ in range(20):
        scene = scene_from_dict(random_scene(rng, "noise.png"), folder=tmp_path)
        for origins, directions, t_max in _shadow_bundles(rng):
            want = cast(scene, origins, directions)
            before = want.t < t_max
            arrays = SceneArrays.of(scene)
            for hits in (
                cast_nearby(scene, arrays, cast, origins, directions, t_max),
                BVH.build(scene).cast(origins, directions, t_max),
            ):
                assert np.array_equal(hits.index[before], want.index[before])
                assert np.array_equal(hits.t[before], want.t[before])
                assert np.all((hits.t >= t_max) | (hits.t == want.t))
            near = objects_near_segments(arrays.boxes, origins, directions, t_max)
            assert set(want.index[before]) - {-1} <= set(near.tolist())
            skipped += len(scene.objects) - len(near)
    assert skipped > 0  # the culling does cull

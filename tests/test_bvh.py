"""The bounding volume hierarchy answers exactly what brute force answers, and skips work."""

import json
from functools import partial

import numpy as np
import pytest

import raykit.render
from conftest import SCENES, random_scene, scene_dict, write_texture
from raykit.bvh import BVH
from raykit.render import cast, render
from raykit.scene import load_scene, scene_from_dict


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
    monkeypatch.setattr(raykit.render, "secondary_caster", lambda s: partial(cast, s))
    brute = render(scene)
    monkeypatch.setattr(raykit.render, "secondary_caster", lambda s: BVH.build(s).cast)
    through_bvh = render(scene)
    assert np.array_equal(brute.rgb, through_bvh.rgb)

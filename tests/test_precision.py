"""float32 rendering: the scene moved to the eye, then intersected in single precision."""

import numpy as np
import pytest

from conftest import SCENES
from raykit.billboards import hit_billboard
from raykit.precision import eye_relative
from raykit.render import render
from raykit.scene import load_scene


@pytest.mark.parametrize("name", ["classic", "cutouts", "orthographic", "far_away"])
def test_float32_changes_no_object_on_the_example_scenes(name):
    scene = load_scene(SCENES / f"{name}.json")
    double, single = render(scene), render(scene, dtype=np.float32)
    assert np.array_equal(double.object_index, single.object_index)
    assert np.allclose(double.t, single.t, rtol=1e-5, equal_nan=True)


def test_float32_at_a_150_degree_view_changes_almost_nothing():
    scene = load_scene(SCENES / "wide_fov.json")
    changed = render(scene).object_index != render(scene, dtype=np.float32).object_index
    assert changed.mean() < 1e-4  # a few grazing pixels at the horizon


def test_eye_relative_scene_keeps_the_geometry_in_float32_and_the_eye_at_the_origin():
    scene = eye_relative(load_scene(SCENES / "far_away.json"))
    assert np.array_equal(scene.camera.eye, np.zeros(3))
    assert scene.spheres[0].center.dtype == np.float32
    board = scene.billboards[1]
    origins = np.zeros((1, 3), np.float32)
    directions = np.array([[-0.3, 0.1, -0.95]], np.float32)
    t, alpha, beta = hit_billboard(origins, directions, board)
    assert t.dtype == np.float32 and alpha.dtype == np.float32


def test_float32_with_adaptive_supersampling_matches_float64():
    scene = load_scene(SCENES / "cutouts.json")
    double = render(scene, 3, adaptive=True)
    single = render(scene, 3, adaptive=True, dtype=np.float32)
    assert np.mean(np.all(np.abs(double.rgb - single.rgb) < 1e-6, axis=-1)) >= 0.999

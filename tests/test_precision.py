"""float32 rendering: the scene moved to the eye, then intersected in single precision."""

import numpy as np
import pytest

from conftest import SCENES
from raykit.billboards import hit_billboard
from raykit.engine.precision import eye_relative
from raykit.io.scene_json import load_scene
from raykit.render import render


@pytest.mark.parametrize("name", ["classic", "cutouts", "orthographic", "far_away"])
def test_float32_changes_no_object_on_the_example_scenes(name):
    scene = load_scene(SCENES / f"{name}.json")
    double, single = render(scene), render(scene, dtype=np.float32)
    assert np.array_equal(double.object_index, single.object_index)
    assert np.allclose(double.t, single.t, rtol=1e-5, equal_nan=True)


def test_float32_at_a_150_degree_view_changes_only_rays_exactly_on_the_floors_edge():
    """wide_fov's eye is at x = 0, 1.2 above a floor whose side edges lie at x = ±6, so the
    edges project to the image lines s = ∓5·t through the image centre. With square pixels,
    the pixel centres on them are c = 1047 - 5r and c = 5r - 448: there alpha is exactly 0
    or 1, a tie that each precision's rounding decides (float64 itself gets -1e-15 on some).
    float32 changes no other pixel's object."""
    scene = load_scene(SCENES / "wide_fov.json")
    assert (scene.camera.width, scene.camera.height) == (600, 300)
    rows, cols = np.nonzero(
        render(scene).object_index != render(scene, dtype=np.float32).object_index
    )
    assert len(rows) > 0  # the ties exist, so this test is about something
    on_an_edge = (cols == 1047 - 5 * rows) | (cols == 5 * rows - 448)
    assert on_an_edge.all(), list(zip(rows[~on_an_edge], cols[~on_an_edge], strict=True))


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

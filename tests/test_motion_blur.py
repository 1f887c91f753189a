"""Motion blur (Cook et al. 1984, FOCG 13.4.5): each ray sees the moving spheres at its own time
in the shutter interval; a sphere is at c + T·v at time T; a still scene and a shutter of no
length change no byte; the blur lies along the sphere's path and keeps its area; the same seed
gives the same bytes; the compiled engine renders the same bytes, and auto judges a moving
scene as any distributed one. Seeded throughout."""

import json
from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENES, scene_dict
from raykit.engine.choice import choose, compiled_available
from raykit.io.scene_json import scene_from_dict
from raykit.render import cast, render
from raykit.sampling import Sampling
from raykit.scene import Scene
from raykit.spheres import center_at


def _small(name: str, **render_settings) -> Scene:
    data = json.loads((SCENES / name).read_text())
    data["camera"].update(width=40, height=28)
    data["render"].update(render_settings)
    return scene_from_dict(data, source=name, folder=SCENES)


def test_a_spheres_centre_at_time_t_is_its_centre_plus_t_times_its_velocity():
    centres = center_at(np.array([1.0, 2, 3]), np.array([0.5, 0, -2]), np.array([0.0, 0.5, 2.0]))
    assert centres.tolist() == [[1.0, 2, 3], [1.25, 2, 2], [2.0, 2, -1]]


def test_a_ray_meets_the_sphere_where_it_is_at_the_rays_time():
    scene = scene_from_dict(scene_dict(version=2, render={"shutter": [0, 1]}))
    scene = replace(scene, velocities=np.array([[3.0, 0, 0]]))  # at x = 3 by the time T = 1
    origins = np.array([[3.0, 0, 5], [3.0, 0, 5], [0.0, 0, 5]])
    directions = np.array([[0.0, 0, -1]] * 3)
    hits = cast(scene, origins, directions, times=np.array([0.0, 1.0, 1.0]))
    assert hits.index.tolist() == [-1, 0, -1]  # not there yet; there; gone from the origin
    assert hits.t[1] == 4.0
    assert cast(scene, origins, directions).index.tolist() == [-1, -1, 0]  # no times: T = 0


def test_a_still_scene_renders_the_same_bytes_whatever_its_shutter():
    data = json.loads((SCENES / "soft_shadows.json").read_text())
    data["camera"].update(width=40, height=30)
    data["render"].update(samples_per_pixel=4)
    plain = render(scene_from_dict(data, folder=SCENES), engine="numpy")
    for shutter in ([0, 0], [0.2, 0.7]):
        data["render"]["shutter"] = shutter
        shuttered = render(scene_from_dict(data, folder=SCENES), engine="numpy")
        assert shuttered.rgb.tobytes() == plain.rgb.tobytes()


@pytest.mark.parametrize("sampler", ["random", "jittered", "sobol"])
def test_a_shutter_of_no_length_shows_the_scene_as_it_stands_at_that_time(sampler):
    scene = _small("motion_blur.json", samples_per_pixel=4, sampler=sampler, shutter=[0.5, 0.5])
    assert scene.moving and not scene.blurred
    moved = replace(scene.at(0.5), sampling=Sampling(4, sampler, 1))  # no shutter: nothing moves
    instant, still = render(scene, engine="numpy"), render(moved, engine="numpy")
    assert instant.rgb.tobytes() == still.rgb.tobytes()
    assert instant.t.tobytes() == still.t.tobytes()


def _coverage(scene: Scene) -> np.ndarray:
    """The share (H, W) of each pixel the red sphere covers, from an unlit copy of the scene
    with only that sphere, white on black."""
    sphere = replace(scene.spheres[0], color=np.ones(3))
    alone = replace(scene, spheres=(sphere,), billboards=(), lights=(), ambient=None,
                    background=np.zeros(3), velocities=scene.velocities[:1])  # fmt: skip
    return render(alone, engine="numpy").rgb[:, :, 0]


def test_the_blur_lies_along_the_spheres_path_and_keeps_its_area():
    blurred = _small("motion_blur.json", samples_per_pixel=64, seed=3)
    begin, end = (_coverage(replace(blurred.at(t), sampling=Sampling(64))) for t in (0, 1))
    streak = _coverage(blurred)
    # it spans from where the sphere starts to where it ends, on the rows the sphere covers
    rows, cols = np.nonzero(streak > 0)
    rows_still, cols_begin = np.nonzero(begin > 0)
    cols_end = np.nonzero(end > 0)[1]
    assert (rows.min(), rows.max()) == (rows_still.min(), rows_still.max())
    assert abs(cols.min() - cols_begin.min()) <= 1 and abs(cols.max() - cols_end.max()) <= 1
    # partly covered along the path (each ray sees the sphere at its own time), where the
    # sphere at one instant is partly covered only along its outline
    partly = lambda coverage: np.count_nonzero((coverage > 0.05) & (coverage < 0.95))  # noqa: E731
    assert partly(streak) > 3 * partly(begin)
    # the mean over the shutter keeps the area the sphere covers at each instant
    assert abs(streak.sum() / begin.sum() - 1) < 0.05


def test_each_pixels_rays_see_the_sphere_at_different_times():
    # a time per pixel would make each pixel all sphere or all background; per ray, the pixels
    # along the path are partly covered
    blurred = _small("motion_blur.json", samples_per_pixel=16)
    streak = _coverage(blurred)
    partly = (streak > 0) & (streak < 1)
    assert np.count_nonzero(partly) > 0.5 * np.count_nonzero(streak)


@pytest.mark.parametrize("sampler", ["random", "jittered", "sobol"])
def test_a_motion_blurred_render_is_the_same_bytes_for_the_same_seed(sampler):
    scene = _small("motion_blur.json", samples_per_pixel=4, sampler=sampler)
    first = render(scene, engine="numpy").rgb
    assert first.tobytes() == render(scene, engine="numpy", skip_hidden=False).rgb.tobytes()
    other = replace(scene, sampling=replace(scene.sampling, seed=2))
    assert first.tobytes() != render(other, engine="numpy").rgb.tobytes()


def test_the_shadow_of_a_moving_sphere_is_cast_at_each_rays_time():
    scene = _small("motion_blur.json", samples_per_pixel=16)
    blurred = render(scene, engine="numpy").rgb.sum(axis=2)
    at_start = render(replace(scene.at(0), sampling=Sampling(16, seed=1)), engine="numpy")
    # where the sphere is never seen, only its shadow changes the floor: the shadow moves with
    # the rays' times (shadow rays at time 0 would leave it where it is at the start)
    floor = (_coverage(scene) == 0) & (at_start.object_index == 2)
    change = (blurred - at_start.rgb.sum(axis=2))[floor]
    assert np.count_nonzero(change < -0.05) > 5  # darker: the shadow, later on
    assert np.count_nonzero(change > 0.05) > 5  # lighter: the shadow at the start, smeared


def test_the_compiled_engine_renders_a_moving_scene_to_the_same_bytes_and_auto_judges_its_rays():
    scene = _small("motion_blur.json", samples_per_pixel=4)
    assert scene.distributed and choose("auto", scene) == "numpy"  # too small to pay numba's load
    if not compiled_available():
        pytest.skip("numba is not installed")
    assert choose("compiled", scene) == "compiled"
    fast, reference = render(scene, engine="compiled"), render(scene, engine="numpy")
    assert np.array_equal(fast.object_index, reference.object_index)
    assert fast.t.tobytes() == reference.t.tobytes()
    assert fast.rgb.tobytes() == reference.rgb.tobytes()  # no highlight: no pow to differ

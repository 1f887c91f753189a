"""The thin-lens camera (FOCG 13.4.3): aperture 0 is the pinhole, to the byte; every ray of an
image point meets on the focal plane, so what lies there stays sharp and the rest blurs; the
lens is a disk of radius aperture/2. Seeded throughout."""

import json
from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENES, scene_dict
from raykit.camera import Camera, rays_through, thin_lens_rays
from raykit.io.scene_json import scene_from_dict
from raykit.rays import dot, length
from raykit.render import render
from raykit.sampling import Sampling

CAMERA = Camera(np.array([1.0, 2, 6]), np.array([0.0, 0.5, 0]), np.array([0.0, 1, 0]), 40, 64,
                48, aperture=0.8, focus_distance=4.5)  # fmt: skip


def _uniforms(count: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).random((count, 2))


def test_aperture_zero_renders_the_pinholes_bytes():
    for name in ("classic_lit.json", "mirror_balls.json"):
        data = json.loads((SCENES / name).read_text())
        data["camera"].update(width=48, height=36)
        pinhole = render(scene_from_dict(data, folder=SCENES), engine="numpy")
        data.update(version=2, render={"samples_per_pixel": 1, "seed": 5})
        data["camera"].update(aperture=0, focus_distance=3)
        lens = render(scene_from_dict(data, folder=SCENES), engine="numpy")
        assert lens.rgb.tobytes() == pinhole.rgb.tobytes()
        assert lens.t.tobytes() == pinhole.t.tobytes()


def test_a_lens_of_no_size_gives_the_pinholes_rays():
    x, y = np.full(50, 20.25), np.full(50, 13.5)
    origins, directions = thin_lens_rays(replace(CAMERA, aperture=0.0), x, y, _uniforms(50))
    pin_origins, pin_directions = rays_through(CAMERA, x, y)
    assert origins.tobytes() == pin_origins.tobytes()
    assert np.allclose(directions, pin_directions, atol=1e-15, rtol=0)


def test_every_ray_of_an_image_point_meets_on_the_focal_plane():
    u, v, w = CAMERA.frame
    for x, y in ((0.5, 0.5), (31.7, 20.2), (63.5, 47.5)):
        origins, directions = thin_lens_rays(CAMERA, np.full(200, x), np.full(200, y),
                                             _uniforms(200))  # fmt: skip
        assert np.allclose(length(directions), 1)
        # the focal plane: w = -f from the eye
        t = (-CAMERA.focus - dot(origins - CAMERA.eye, w)) / dot(directions, w)
        meet = origins + t[:, None] * directions
        assert np.allclose(meet, meet[0], atol=1e-12)
        pin_origin, pin_direction = rays_through(CAMERA, np.array([x]), np.array([y]))
        along = CAMERA.focus / -dot(pin_direction, w)[0]
        assert np.allclose(meet[0], pin_origin[0] + along * pin_direction[0], atol=1e-12)


def test_the_rays_start_on_the_lens_disk_of_radius_half_the_aperture():
    u, v, w = CAMERA.frame
    origins, _ = thin_lens_rays(CAMERA, np.full(4000, 10.0), np.full(4000, 10.0),
                                _uniforms(4000, 1))  # fmt: skip
    offset = origins - CAMERA.eye
    assert np.allclose(dot(offset, w), 0, atol=1e-15)  # in the lens plane
    radius = length(offset)
    assert radius.max() <= CAMERA.aperture / 2 + 1e-15
    assert radius.max() > 0.99 * CAMERA.aperture / 2  # the aperture is the diameter, all of it
    assert abs(np.mean(radius < CAMERA.aperture / 4) - 0.25) < 0.03  # uniform over the disk


def _board_scene(depth: float, aperture: float) -> dict:
    """A half-black, half-white billboard across the view at distance ``depth`` from the eye,
    seen through a lens focused at 5, 16 jittered samples per pixel."""
    data = scene_dict(spheres=[], background=[0, 0, 1], version=2)
    data["camera"].update(eye=[0, 0, 5], lookat=[0, 0, 0], width=32, height=24, aperture=aperture,
                          focus_distance=5)  # fmt: skip
    z = 5 - depth
    data["billboards"] = [
        {"upper_left": [-9, 9, z], "lower_left": [-9, -9, z], "upper_right": [0, 9, z],
         "color": [0, 0, 0]},
        {"upper_left": [0, 9, z], "lower_left": [0, -9, z], "upper_right": [9, 9, z],
         "color": [1, 1, 1]},
    ]  # fmt: skip
    data["render"] = {"samples_per_pixel": 16, "sampler": "jittered", "seed": 3}
    return data


@pytest.mark.parametrize("aperture", [0.5, 2.0])
def test_the_focal_plane_stays_sharp_and_the_rest_blurs(aperture):
    def image(depth, a):
        return render(scene_from_dict(_board_scene(depth, a)), engine="numpy").rgb[..., 0]

    # on the focal plane: the lens changes nothing but rounding
    assert np.abs(image(5, aperture) - image(5, 0.0)).max() < 1e-9
    # off it: the edge spreads over more pixels, the more the wider the lens
    blurred = image(2.5, aperture)
    grey = np.count_nonzero((blurred[12] > 0.02) & (blurred[12] < 0.98))
    assert grey >= (2 if aperture == 0.5 else 6)
    assert np.count_nonzero((image(2.5, 0.0)[12] > 0.02) & (image(2.5, 0.0)[12] < 0.98)) <= 1


def test_a_lens_render_is_the_same_bytes_for_the_same_seed():
    data = json.loads((SCENES / "depth_of_field.json").read_text())
    data["camera"].update(width=40, height=30)
    data["render"].update(samples_per_pixel=4)
    scene = scene_from_dict(data, folder=SCENES)
    first = render(scene, engine="numpy").rgb
    assert first.tobytes() == render(scene, engine="numpy").rgb.tobytes()
    other = replace(scene, sampling=Sampling(4, "jittered", 2))
    assert first.tobytes() != render(other, engine="numpy").rgb.tobytes()

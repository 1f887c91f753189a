import math

import numpy as np
import pytest

from raykit.camera import (
    Camera,
    DegenerateFrameError,
    camera_frame,
    image_plane_points,
    pixel_points,
    rays_through,
    sample_offsets,
)
from raykit.planes import hit_plane
from raykit.rays import normalize


def make_camera(**kw) -> Camera:
    args = dict(
        eye=np.array([1.0, 2.0, 3.0]),
        lookat=np.array([-2.0, 0.5, -4.0]),
        up=np.array([0.3, 1.0, 0.2]),  # deliberately not orthogonal to the view direction
        fov_angle=37.0,
        width=31,
        height=21,
    )
    args.update(kw)
    return Camera(**args)


def angle_deg(a, b) -> float:
    a, b = normalize(a), normalize(b)
    return math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), a @ b))


def test_frame_is_orthonormal_right_handed_with_w_pointing_back_to_the_eye():
    cam = make_camera()
    u, v, w = cam.frame
    assert np.allclose([u @ u, v @ v, w @ w], 1.0)
    assert np.allclose([u @ v, v @ w, w @ u], 0.0)
    assert np.allclose(np.cross(u, v), w)
    assert np.allclose(w, normalize(cam.eye - cam.lookat))
    assert v @ cam.up > 0  # v is the up of the image


@pytest.mark.parametrize("projection", ["perspective", "orthographic"])
def test_centre_pixel_ray_points_at_lookat(projection):
    cam = make_camera(projection=projection)
    x, y = np.array([15.5]), np.array([10.5])  # centre of pixel (10, 15) of 21 x 31
    origins, directions = rays_through(cam, x, y)
    to_lookat = cam.lookat - origins[0]
    assert angle_deg(directions[0], to_lookat) == pytest.approx(0.0, abs=1e-6)


def test_edge_rays_make_the_half_fov_angles():
    cam = make_camera(width=40, height=30)
    view = cam.lookat - cam.eye
    _, d = rays_through(cam, np.array([20.0, 0.0, 20.0]), np.array([0.0, 15.0, 30.0]))
    half_vertical = cam.fov_angle / 2
    half_horizontal = math.degrees(math.atan(math.tan(math.radians(half_vertical)) * 40 / 30))
    assert angle_deg(d[0], view) == pytest.approx(half_vertical)  # top edge, middle column
    assert angle_deg(d[1], view) == pytest.approx(half_horizontal)  # left edge, middle row
    assert angle_deg(d[2], view) == pytest.approx(half_vertical)  # bottom edge


def test_row_zero_is_the_top_and_column_zero_the_left():
    cam = make_camera()
    u, v, _ = cam.frame
    _, d = rays_through(cam, np.array([0.5, 30.5, 15.5]), np.array([10.5, 10.5, 0.5]))
    assert d[0] @ u < 0 < d[1] @ u
    assert d[2] @ v > 0


def test_orthographic_and_perspective_frame_the_lookat_plane_identically():
    x, y = pixel_points(31, range(21), 0.25, 0.75)
    hits = []
    for projection in ("perspective", "orthographic"):
        cam = make_camera(projection=projection)
        o, d = rays_through(cam, x, y)
        t = hit_plane(o, d, cam.lookat, cam.frame[2])
        hits.append(o + t[:, None] * d)
    assert np.allclose(hits[0], hits[1], atol=1e-9)


def test_orthographic_rays_are_parallel_to_minus_w():
    cam = make_camera(projection="orthographic")
    _, d = rays_through(cam, *pixel_points(31, range(21)))
    assert np.allclose(d, -cam.frame[2])


def test_perspective_directions_are_unit_length():
    _, d = rays_through(make_camera(), *pixel_points(31, range(21)))
    assert np.allclose(np.linalg.norm(d, axis=1), 1.0)


def test_sample_offsets_are_a_regular_grid_of_subpixel_centres():
    assert np.array_equal(sample_offsets(1), [[0.5, 0.5]])
    grid = sample_offsets(2)
    assert sorted(map(tuple, grid)) == [(0.25, 0.25), (0.25, 0.75), (0.75, 0.25), (0.75, 0.75)]
    assert np.array_equal(sample_offsets(3)[4], [0.5, 0.5])  # odd n contains the centre


def test_pixel_points_are_row_major():
    x, y = pixel_points(3, range(1, 3))
    assert np.array_equal(x, [0.5, 1.5, 2.5, 0.5, 1.5, 2.5])
    assert np.array_equal(y, [1.5, 1.5, 1.5, 2.5, 2.5, 2.5])


@pytest.mark.parametrize(
    ("eye", "lookat", "up", "culprit"),
    [
        ([0, 0, 1], [0, 0, 1], [0, 1, 0], "lookat"),
        ([0, 0, 1], [0, 0, 0], [0, 0, 0], "up"),
        ([0, 0, 1], [0, 0, 0], [0, 0, -3], "up"),
    ],
)
def test_degenerate_frames_are_refused_naming_the_input(eye, lookat, up, culprit):
    with pytest.raises(DegenerateFrameError) as info:
        camera_frame(np.array(eye, float), np.array(lookat, float), np.array(up, float))
    assert info.value.culprit == culprit


def test_slides_ray_e_plus_t_s_minus_e_is_on_the_image_plane_at_t_one_along_the_unit_ray():
    camera = make_camera()
    x, y = pixel_points(camera.width, range(camera.height))
    s = image_plane_points(camera, x, y)  # the slide's s: the pixel's point on the image plane
    e = camera.eye
    _, _, w = camera.frame
    at_one = e + 1.0 * (s - e)  # p(1) = e + 1·(s - e)
    assert np.allclose((at_one - camera.lookat) @ w, 0, atol=1e-12)  # on the plane
    assert np.allclose(at_one, s)
    origins, d = rays_through(camera, x, y)  # raykit's: the same line, unit length
    assert np.array_equal(origins, np.broadcast_to(e, origins.shape))
    assert np.allclose(d, normalize(s - e), atol=1e-15)
    # with the unit direction the plane is met at t = |s - e|, its distance from the eye
    assert np.allclose(hit_plane(origins, d, camera.lookat, w), np.linalg.norm(s - e, axis=1))


def test_image_plane_is_at_w_equals_minus_d_in_the_cameras_own_coordinates():
    camera = make_camera()
    u, v, w = camera.frame
    x, y = pixel_points(camera.width, range(camera.height))
    relative = image_plane_points(camera, x, y) - camera.eye
    assert np.allclose(relative @ w, -camera.d, rtol=0, atol=1e-12)
    assert camera.d == pytest.approx(np.linalg.norm(camera.lookat - camera.eye))

"""The 3D line-scan camera (raykit.linescan.sweep3d): a 3D camera one pixel high, a car driving
through its plane of view, one render a scan, the scans side by side."""

import numpy as np
import pytest
from PIL import Image

from conftest import SCENES
from raykit.camera import pixel_points, rays_through
from raykit.cli import main
from raykit.io.scene_json import load_scene
from raykit.linescan.camera import pixel_x
from raykit.linescan.sweep3d import sweep_3d
from raykit.rays import length as vector_length
from raykit.rays import normalize

CAR = SCENES / "linescan3d" / "passing_car.json"
CAR_SCANS = 1200  # the command's --scans in docs/make_images.py


@pytest.fixture(scope="module")
def car_sweep():
    scene = load_scene(CAR)
    return scene, sweep_3d(scene, CAR_SCANS, engine="numpy")


def _names(scene) -> list[str]:
    return [o.name for o in scene.objects]


def test_car_is_as_many_scans_long_as_its_length_over_its_speed(car_sweep):
    scene, taken = car_sweep
    # the hand count: the body is 4.2 long and moves 0.004 a scan, so it is in the plane of view
    # for 4.2 / 0.004 = 1050 scans (its ends cross the plane between scans, at 76.25 and 1126.25)
    body = _names(scene).index("body")
    length = float(vector_length(scene.objects[body].upper_right - scene.objects[body].upper_left))
    speed = float(vector_length(scene.velocities[body]))
    assert round(length / speed) == 1050
    moving = np.flatnonzero(np.any(scene.velocities != 0, axis=1))
    mid_body = 356  # the row that sees y = 0.675, halfway up the body: 2.101 - (i + 0.5)·0.004
    seen = np.isin(taken.index[mid_body], moving)
    assert seen.sum() == 1050
    assert np.flatnonzero(seen)[[0, -1]].tolist() == [77, 1126]  # one run, no gap


def test_car_sweep_has_a_column_per_scan_with_the_sky_on_top_and_the_road_below(car_sweep):
    scene, taken = car_sweep
    assert taken.image.shape == (scene.camera.width, CAR_SCANS, 3)
    road = _names(scene).index("road")
    assert (taken.index[0] == -1).all()  # the sky (the background) in the top row
    assert (taken.index[-1] == road).all()
    wheels = [_names(scene).index(n) for n in ("front wheel", "rear wheel")]
    bottom_of_car = taken.index[499]  # y = 0.103: the wheels, and the road between them
    assert set(bottom_of_car.tolist()) == {road, *wheels}


def test_one_row_camera_rays_are_the_slides_p_i_e_plus_x_i_u_plus_D_w():
    camera = load_scene(CAR).camera
    assert camera.height == 1
    origins, directions = rays_through(camera, *pixel_points(camera.width, range(1)))
    u, _, w = camera.frame
    # the row's own field of view: one square pixel is fov_angle high, so the row is width
    # times as wide on the image plane, and D = 1/tan(fov_row/2)
    D = 1 / (camera.width * np.tan(np.radians(camera.fov_angle) / 2))
    x = pixel_x(camera.width)
    slide = normalize(x[:, None] * u + D * -w)  # raykit's w points back: -w is the slide's w
    assert np.allclose(directions, slide, rtol=0, atol=1e-12)
    assert np.array_equal(origins, np.broadcast_to(camera.eye, origins.shape))


def test_scene_at_a_scan_moves_only_what_has_a_velocity():
    scene = load_scene(CAR)
    later = scene.at(100)
    for before, after, velocity in zip(scene.objects, later.objects, scene.velocities, strict=True):
        start = getattr(before, "center", getattr(before, "upper_left", None))
        end = getattr(after, "center", getattr(after, "upper_left", None))
        assert np.allclose(end - start, 100 * velocity, rtol=0, atol=1e-12)
    assert load_scene(SCENES / "classic.json").velocities is None


def test_sweep_command_writes_the_car_a_column_per_scan(tmp_path, car_sweep):
    out = tmp_path / "car.png"
    assert main(["sweep", str(CAR), "-o", str(out), "--scans", "40", "--engine", "numpy"]) == 0
    picture = np.asarray(Image.open(out))
    assert picture.shape == (600, 40, 3)


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ([], "a 3D scene has no scans field: give --scans M"),
        (["--scans", "5", "--diagram", "d.png"], "--diagram: the sweep diagram is drawn for 2D"),
    ],
)
def test_sweep_of_a_3d_scene_refuses_in_one_line(tmp_path, capsys, extra, words):
    out = tmp_path / "car.png"
    assert main(["sweep", str(CAR), "-o", str(out), *extra]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and not out.exists()


def test_sweep_of_a_3d_scene_needs_a_camera_one_pixel_high(tmp_path, capsys):
    out = tmp_path / "sweep.png"
    assert main(["sweep", str(SCENES / "classic.json"), "-o", str(out), "--scans", "3"]) == 2
    err = capsys.readouterr().err
    assert "classic.json: camera.height: a line-scan sweep needs a camera one pixel high" in err
    assert not out.exists()

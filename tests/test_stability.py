"""Stress tests of numerical stability: each extreme case against exact rational arithmetic or
an independent tracer, with and without the tiles."""

from fractions import Fraction

import numpy as np
import pytest

from conftest import SCENES
from exact import exact_sphere_hit
from independent_tracer import trace_object_index
from raykit.camera import pixel_points, rays_through
from raykit.io.scene_json import scene_from_dict
from raykit.render import render
from raykit.spheres import hit_sphere_textbook


def _json(path):
    import json

    scene = json.loads(path.read_text())
    scene.pop("$schema", None)
    return scene


@pytest.mark.parametrize("skip_hidden", [False, True])
def test_tiny_far_sphere_is_drawn_exactly_where_exact_arithmetic_says(skip_hidden):
    # radius 1e-3 at 1e5: seen under 1e-8 rad; a fov of 4e-8 rad spans it in 23 pixels
    fov = float(np.degrees(4e-8))
    data = {
        "camera": {
            "eye": [0, 0, 1e5],
            "lookat": [2e-4, -1e-4, 0],
            "up": [0, 1, 0],
            "fov_angle": fov,
            "width": 23,
            "height": 23,
        },
        "spheres": [{"center": [0, 0, 0], "radius": 1e-3, "color": [1, 1, 1]}],
    }
    scene = scene_from_dict(data)
    index = render(scene, skip_hidden=skip_hidden).object_index
    origins, directions = rays_through(scene.camera, *pixel_points(23, range(23)))
    exact = np.array(
        [
            exact_sphere_hit(o, d, np.zeros(3), 1e-3)
            for o, d in zip(origins, directions, strict=True)
        ]
    ).reshape(23, 23)
    assert 50 < exact.sum() < 23 * 23 - 50  # the silhouette runs through the image
    assert np.array_equal(index == 0, exact)
    textbook = np.isfinite(hit_sphere_textbook(origins, directions, np.zeros(3), 1e-3))
    assert (textbook.reshape(23, 23) != exact).sum() > 10  # where the textbook form fails


@pytest.mark.parametrize("offset", [1e6, 1e7])
def test_scene_far_from_the_origin_shows_the_same_objects(offset):
    near = _json(SCENES / "classic.json")
    near["camera"].update(width=160, height=120)
    far = _json(SCENES / "classic.json")
    far["camera"].update(width=160, height=120)
    shift = np.array([offset, -offset / 2, offset / 3])
    for key in ("eye", "lookat"):
        far["camera"][key] = (np.array(far["camera"][key]) + shift).tolist()
    for sphere in far["spheres"]:
        sphere["center"] = (np.array(sphere["center"]) + shift).tolist()
    for board in far["billboards"]:
        for key in ("upper_left", "upper_right", "lower_left"):
            board[key] = (np.array(board[key]) + shift).tolist()
    a = render(scene_from_dict(near, folder=SCENES)).object_index
    b = render(scene_from_dict(far, folder=SCENES)).object_index
    assert np.mean(a == b) >= 0.999


@pytest.mark.parametrize(
    ("fov", "width", "height"),
    [(0.01, 31, 17), (179.9, 31, 17), (45, 1, 1), (45, 1, 37), (45, 37, 1), (120, 3, 2)],
)
def test_extreme_fields_of_view_and_image_shapes_agree_with_an_independent_tracer(
    fov, width, height
):
    data = _json(SCENES / "classic.json")
    data["camera"].update(fov_angle=fov, width=width, height=height)
    if fov < 1:  # look exactly at the red ball's silhouette
        eye, center = np.array(data["camera"]["eye"], float), np.array([0.0, 1.0, 0.0])
        distance = np.linalg.norm(center - eye)
        angle = np.arcsin(1.0 / distance)
        toward = (center - eye) / distance
        data["camera"]["lookat"] = (
            eye + distance * (np.cos(angle) * toward + np.sin(angle) * np.array([1.0, 0, 0]))
        ).tolist()
    ours = render(scene_from_dict(data, folder=SCENES)).object_index
    theirs = np.array(trace_object_index(data, SCENES))
    assert ours.shape == (height, width)
    assert np.mean(ours == theirs) >= 0.99
    if fov < 1:
        assert 0 < np.mean(ours == 0) < 1  # the silhouette crosses the tiny view


def test_billboard_edge_on_is_not_seen_and_grazing_rays_agree_with_exact_arithmetic():
    # the eye in the plane of a billboard: every ray runs along the plane or leaves it at t = 0
    edge_on = {
        "camera": {
            "eye": [-2, 0, 5],
            "lookat": [-2, 0, 0],
            "up": [0, 1, 0],
            "fov_angle": 40,
            "width": 15,
            "height": 15,
        },
        "billboards": [
            {
                "upper_left": [-2, 1, 0],
                "lower_left": [-2, -1, 0],
                "upper_right": [-2, 1, -4],
                "color": [1, 1, 1],
            }
        ],
    }
    assert (render(scene_from_dict(edge_on)).object_index == -1).all()
    # grazing: the eye 1e-9 above a floor billboard, looking along it
    graze = {
        "camera": {
            "eye": [0, 1e-9, 2],
            "lookat": [0, 1e-9, -3],
            "up": [0, 1, 0],
            "fov_angle": 30,
            "width": 21,
            "height": 21,
        },
        "billboards": [
            {
                "upper_left": [-3, 0, -3],
                "lower_left": [-3, 0, 3],
                "upper_right": [3, 0, -3],
                "color": [1, 1, 1],
            }
        ],
    }
    scene = scene_from_dict(graze)
    index = render(scene).object_index
    origins, directions = rays_through(scene.camera, *pixel_points(21, range(21)))
    exact = []
    for o, d in zip(origins, directions, strict=True):
        o, d = [Fraction(float(x)) for x in o], [Fraction(float(x)) for x in d]
        if d[1] == 0:
            exact.append(False)  # parallel to the floor
            continue
        t = -o[1] / d[1]
        x, z = o[0] + t * d[0], o[2] + t * d[2]
        exact.append(t > 0 and -3 <= x <= 3 and -3 <= z <= 3)
    exact = np.array(exact).reshape(21, 21)
    assert exact[11:].all() and not exact[:11].any()  # below the horizon only
    assert np.array_equal(index == 0, exact)


def test_camera_inside_a_sphere_at_large_coordinates_sees_its_inside_everywhere():
    data = {
        "camera": {
            "eye": [1e7, 1e7, 1e7],
            "lookat": [1e7 + 1, 1e7, 1e7],
            "up": [0, 0, 1],
            "fov_angle": 90,
            "width": 17,
            "height": 9,
        },
        "spheres": [
            {"center": [1e7 + 0.5, 1e7, 1e7], "radius": 3, "color": [1, 0, 0]},
            {"center": [1e7 + 1.5, 1e7, 1e7], "radius": 0.5, "color": [0, 1, 0]},
        ],
    }
    index = render(scene_from_dict(data)).object_index
    assert set(np.unique(index)) == {0, 1}
    assert index[4, 8] == 1  # the small sphere in the middle, in front of the far wall

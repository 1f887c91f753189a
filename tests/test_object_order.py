import numpy as np
import pytest

from conftest import SCENES
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.object_order import covered_pixels, render_object_order
from raykit.render import render

EXAMPLES = sorted(p.stem for p in SCENES.glob("*.json"))


@pytest.mark.parametrize("name", EXAMPLES)
def test_object_order_gives_the_ray_tracers_object_index_on_every_example_scene(name):
    scene = load_scene(SCENES / f"{name}.json")
    traced = render(scene)
    drawn = render_object_order(scene)
    assert (drawn.object_index == traced.object_index).all()
    assert (drawn.t == traced.t).all()


def test_object_order_gives_the_ray_tracers_flat_colours_on_an_unlit_scene():
    scene = load_scene(SCENES / "cutouts.json")  # cut-out holes: the object behind shows
    assert (render_object_order(scene).rgb == render(scene).rgb).all()


def test_objects_at_the_same_depth_keep_the_lower_index_as_the_ray_tracer_does():
    sphere = {"center": [0, 0, 0], "radius": 1, "color": [1, 0, 0]}
    twin = {"center": [0, 0, 0], "radius": 1, "color": [0, 0, 1]}
    scene = scene_from_dict({**_camera(), "spheres": [sphere, twin]})
    drawn = render_object_order(scene)
    assert set(np.unique(drawn.object_index)) == {-1, 0}
    assert (drawn.object_index == render(scene).object_index).all()


def test_random_spheres_give_the_same_index_image_both_ways():
    rng = np.random.default_rng(19)
    spheres = [
        {
            "center": rng.uniform([-3, -2, -6], [3, 2, 1]).tolist(),
            "radius": float(rng.uniform(0.1, 1.0)),
            "color": rng.uniform(0, 1, 3).tolist(),
        }
        for _ in range(60)
    ]
    scene = scene_from_dict({**_camera(), "spheres": spheres})
    assert (render_object_order(scene).object_index == render(scene).object_index).all()


def test_covered_pixels_are_those_whose_centres_lie_in_the_rectangle():
    rows, cols = covered_pixels((1.5, 3.6, 0.0, 1.4), width=10, height=10)
    assert sorted(set(cols.tolist())) == [1, 2, 3]  # centres 1.5, 2.5, 3.5
    assert sorted(set(rows.tolist())) == [0]  # centre 0.5 (1.5 > 1.4)
    assert covered_pixels((0.0, 0.4, 0.0, 9.0), 10, 10)[0].size == 0


def _camera() -> dict:
    return {
        "camera": {
            "eye": [0, 0, 6],
            "lookat": [0, 0, 0],
            "up": [0, 1, 0],
            "fov_angle": 50,
            "width": 64,
            "height": 48,
        }
    }

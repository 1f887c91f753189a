import math

import numpy as np
import pytest

from raykit.cli import main
from raykit.io.errors import SceneError
from raykit.io.nff import scene_from_nff
from raykit.io.scene_json import scene_from_dict
from raykit.render import render

BALLS = """# a small scene in the SPD's NFF
v
from 2.1 1.3 1.7
at 0 0 0
up 0 0 1
angle 45
hither 0.01
resolution 41 41
b 0.078 0.361 0.753
l 4 3 2
l 1 -4 4 1 1 1
f 1 0.75 0.33 0.8 0 3 0 0
s 0 0 0 0.5
f 0.2 0.6 0.3 1 0 0 0 0
s 0.6 0.3 0.2 0.2
p 4
12 12 -0.5
-12 12 -0.5
-12 -12 -0.5
12 -12 -0.5
"""


def test_nff_reads_view_spheres_parallelograms_and_colours():
    scene = scene_from_nff(BALLS.splitlines(), "balls.nff")
    camera = scene.camera
    assert (camera.width, camera.height) == (41, 41)
    assert np.allclose(camera.eye, [2.1, 1.3, 1.7]) and np.allclose(camera.up, [0, 0, 1])
    assert len(scene.spheres) == 2 and len(scene.billboards) == 1
    assert np.allclose(scene.spheres[1].color, [0.2, 0.6, 0.3])
    assert np.allclose(scene.background, [0.078, 0.361, 0.753])
    assert np.allclose(scene.billboards[0].a, [-24, 0, 0])


def test_nff_angle_is_between_the_centres_of_the_outermost_pixels():
    scene = scene_from_nff(BALLS.splitlines())
    camera = scene.camera
    Hp = camera.plane_size[1]
    centre_to_centre = 2 * math.degrees(math.atan((Hp / 2) * (1 - 1 / 41) / camera.d))
    assert centre_to_centre == pytest.approx(45)


def test_nff_renders_as_the_same_scene_written_in_json():
    scene = scene_from_nff(BALLS.splitlines())
    camera = scene.camera
    data = {
        "camera": {
            "eye": [2.1, 1.3, 1.7],
            "lookat": [0, 0, 0],
            "up": [0, 0, 1],
            "fov_angle": camera.fov_angle,
            "width": 41,
            "height": 41,
        },
        "background": [0.078, 0.361, 0.753],
        "lights": [
            {"type": "point", "position": [4, 3, 2]},
            {"type": "point", "position": [1, -4, 4], "color": [1, 1, 1]},
        ],
        "spheres": [
            {
                "center": [0, 0, 0],
                "radius": 0.5,
                "color": [1, 0.75, 0.33],
                "diffuse": [0.8 * 1, 0.8 * 0.75, 0.8 * 0.33],
            },
            {
                "center": [0.6, 0.3, 0.2],
                "radius": 0.2,
                "color": [0.2, 0.6, 0.3],
                "diffuse": [0.2, 0.6, 0.3],
            },
        ],
        "billboards": [
            {
                "upper_left": [12, 12, -0.5],
                "upper_right": [-12, 12, -0.5],
                "lower_left": [12, -12, -0.5],
                "color": [0.2, 0.6, 0.3],
                "diffuse": [0.2, 0.6, 0.3],
            }
        ],
    }
    assert np.array_equal(render(scene).rgb, render(scene_from_dict(data)).rgb)


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ("c 0 0 0 1 0 0 1 1", "line 21: cones and cylinders: not supported"),
        (
            "p 3\n0 0 0\n1 0 0\n0 1 0",
            "line 21: a polygon of 3 vertices that is not a parallelogram",
        ),
        ("s 0 0 x 1", "line 21: expected 4 numbers after 's'"),
        ("zz 1 2", "line 21: the entity 'zz': not supported"),
    ],
)
def test_unsupported_nff_is_one_line_naming_the_line(extra, words):
    with pytest.raises(SceneError) as info:
        scene_from_nff((BALLS + extra).splitlines(), "balls.nff")
    assert str(info.value).startswith("balls.nff: line 21: ") and words in str(info.value)


def test_render_command_reads_nff_files(tmp_path, capsys):
    path = tmp_path / "balls.nff"
    path.write_text(BALLS)
    assert main(["render", str(path), "-o", str(tmp_path / "balls.png")]) == 0
    assert "(41x41" in capsys.readouterr().out
    path.write_text(BALLS.replace("resolution 41 41\n", ""))
    assert main(["render", str(path), "-o", str(tmp_path / "x.png")]) == 2
    assert "view: missing resolution" in capsys.readouterr().err


def test_nff_surface_ks_is_the_highlight_and_the_mirror_and_lights_make_it_lit():
    lines = BALLS.replace("f 0.2 0.6 0.3 1 0 0 0 0", "f 0.2 0.6 0.3 0.5 0.4 20 0 0").splitlines()
    scene = scene_from_nff(lines)
    sphere = scene.spheres[1]
    assert np.allclose(sphere.material.diffuse, [0.1, 0.3, 0.15])
    assert np.allclose(sphere.material.specular, 0.4) and np.allclose(sphere.material.mirror, 0.4)
    assert sphere.material.shininess == 20
    assert scene.lit and len(scene.lights) == 2
    assert np.allclose(scene.lights[0].color, 1) and np.allclose(
        scene.lights[0].position, [4, 3, 2]
    )
    flat = scene_from_nff([line for line in lines if not line.startswith("l ")])
    assert not flat.lit

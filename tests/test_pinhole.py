import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from conftest import SCENES  # noqa: E402
from raykit.diagrams.pinhole import pinhole_figure  # noqa: E402
from raykit.io.linescan_json import load_line_scene  # noqa: E402
from raykit.io.scene_json import load_scene  # noqa: E402
from raykit.linescan.diagrams import paths_of_light  # noqa: E402
from raykit.pinhole import render_obscura  # noqa: E402
from raykit.render import render  # noqa: E402


@pytest.mark.parametrize("name", ["classic", "cutouts", "wide_fov"])
def test_camera_obscura_picture_is_the_pinhole_render_turned_half_a_turn(name):
    scene = load_scene(SCENES / f"{name}.json")
    camera = scene.camera
    wall = render_obscura(scene).index.reshape(camera.height, camera.width)
    upright = render(scene).object_index
    assert (wall == upright[::-1, ::-1]).mean() > 0.999
    assert (wall != upright).mean() > 0.5  # and really not the upright picture


def test_pinhole_figure_shows_both_pictures_and_the_crossing_rays():
    figure = pinhole_figure(load_scene(SCENES / "classic.json"))
    side, wall, upright = figure.axes
    assert len(wall.images) == 1 and len(upright.images) == 1
    crossing = [line for line in side.lines if len(line.get_xdata()) == 3]
    assert len(crossing) == 9
    for line in crossing:  # wall -> hole -> scene: the middle point is the hole, at (0, 0)
        assert line.get_xdata()[1] == pytest.approx(0) and line.get_ydata()[1] == pytest.approx(0)
        assert line.get_xdata()[0] < 0 < line.get_xdata()[2]
        # a straight line through the hole: the wall end is on the other side in height
        assert (
            np.sign(line.get_ydata()[0]) == -np.sign(line.get_ydata()[2])
            or abs(line.get_ydata()[0]) < 1e-9
        )
    plt.close(figure)


def test_paths_of_light_most_photons_never_reach_the_image():
    scene = load_line_scene(SCENES / "linescan" / "slide.json")
    figure = paths_of_light(scene, (3.0, 4.5), photons=90, seed=0)
    title = figure.axes[0].get_title()
    hit = int(title.split(": ")[1].split(" hit")[0])
    arrive = int(title.split(", ")[1].split(" bounce")[0])
    assert 0 < arrive < hit < 90
    solid = [line for line in figure.axes[0].lines if len(line.get_xdata()) == 3]
    assert len(solid) == arrive  # light -> surface -> eye
    plt.close(figure)

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from conftest import SCENES  # noqa: E402
from raykit.io.linescan_json import load_line_scene  # noqa: E402
from raykit.linescan.diagrams import ray_diagram, sweep_diagram  # noqa: E402
from raykit.linescan.scan import scan  # noqa: E402


def _collection(figure, gid):
    found = [c for ax in figure.axes for c in ax.collections if c.get_gid() == gid]
    assert len(found) == 1
    return np.array(found[0].get_segments())


@pytest.mark.parametrize("name", ["slide", "passing_car", "conveyor"])
def test_drawn_rays_end_exactly_at_the_tracer_hit_points(name):
    scene = load_line_scene(SCENES / "linescan" / f"{name}.json")
    figure = ray_diagram(scene, every=1)
    taken = scan(scene)
    hit = np.flatnonzero(taken.index >= 0)
    segments = _collection(figure, "rays-hit")
    assert np.array_equal(segments[:, 0], taken.origins[hit])
    assert np.array_equal(segments[:, 1], taken.hit_points[hit])
    missed = _collection(figure, "rays-missed") if (taken.index < 0).any() else np.empty((0, 2))
    assert len(segments) + len(missed) == scene.camera.pixels
    plt.close(figure)


def test_misses_are_drawn_to_the_edge_of_the_frame():
    scene = load_line_scene(SCENES / "linescan/slide.json")
    figure = ray_diagram(scene, every=1)
    ax = figure.axes[0]
    ends = _collection(figure, "rays-missed")[:, 1]
    on_x_edge = np.isclose(ends[:, [0]], ax.get_xlim()).any(axis=1)
    on_y_edge = np.isclose(ends[:, [1]], ax.get_ylim()).any(axis=1)
    assert len(ends) == 1
    assert (on_x_edge | on_y_edge).all()
    plt.close(figure)


def test_every_kth_ray_is_drawn_and_at_most_24_by_default():
    scene = load_line_scene(SCENES / "linescan/passing_car.json")  # 400 pixels
    figure = ray_diagram(scene, every=25)
    drawn = sum(
        len(c.get_segments())
        for c in figure.axes[0].collections
        if c.get_gid() in ("rays-hit", "rays-missed")
    )
    assert drawn == 16
    plt.close(figure)
    figure = ray_diagram(scene)
    drawn = sum(
        len(c.get_segments())
        for c in figure.axes[0].collections
        if c.get_gid() in ("rays-hit", "rays-missed")
    )
    assert drawn <= 24
    plt.close(figure)


def test_diagram_draws_into_a_given_axes_with_equal_aspect():
    figure, ax = plt.subplots()
    returned = ray_diagram(load_line_scene(SCENES / "linescan/slide.json"), ax=ax)
    assert returned is figure and len(figure.axes) == 1
    assert ax.get_aspect() == 1.0
    plt.close(figure)


def test_sweep_diagram_shows_three_times_and_the_growing_image():
    figure = sweep_diagram(load_line_scene(SCENES / "linescan/conveyor.json"), scans=30)
    assert len(figure.axes) == 6
    images = [ax.images[0].get_array() for ax in figure.axes[3:]]
    assert all(img.shape == (30, 192, 3) for img in images)
    plt.close(figure)


def test_pixel_formulas_draws_the_centres_and_the_slides_positions_one_row_per_count():
    from raykit.linescan.diagrams import pixel_formulas

    figure = pixel_formulas((8, 7))
    ax = figure.axes[0]
    marks = [(line.get_marker(), len(line.get_xdata())) for line in ax.lines if line.get_marker()]
    assert ("o", 8) in marks and ("x", 9) in marks  # N = 8: one slide position too many
    assert ("o", 7) in marks and ("x", 7) in marks


@pytest.mark.parametrize("name", ["passing_car", "conveyor"])
def test_sweep_diagram_panels_share_one_frame(name):
    # a frame per panel made the (moving) camera seem to jump between them
    figure = sweep_diagram(load_line_scene(SCENES / f"linescan/{name}.json"), scans=40)
    worlds = figure.axes[:3]
    assert len({ax.get_xlim() for ax in worlds}) == 1
    assert len({ax.get_ylim() for ax in worlds}) == 1
    plt.close(figure)


@pytest.mark.parametrize("fov_angle", [120, 170])
def test_a_wide_fov_angle_frames_what_the_camera_looks_at_with_clear_labels(fov_angle):
    # at 170° the few rays drawn all missed, the frame shrank to the eye, and the fov_angle
    # label lay on the rays (notebook 02's fov_angle slider)
    from dataclasses import replace

    from raykit.io.images import figure_png
    from raykit.io.legibility import read_layout

    slide = load_line_scene(SCENES / "linescan/slide.json")
    scene = replace(slide, camera=replace(slide.camera, fov_angle=fov_angle))
    figure = ray_diagram(scene)
    (x0, x1), (y0, y1) = figure.axes[0].get_xlim(), figure.axes[0].get_ylim()
    for ball in scene.balls:  # the slide's balls are all in front of the eye, in view
        (cx, cy), r = ball.center, ball.radius
        assert x0 <= cx - r and cx + r <= x1 and y0 <= cy - r and cy + r <= y1, ball.center
    layout = read_layout(figure_png(figure))
    assert not layout.problems, layout.problems

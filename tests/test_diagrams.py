import io
import json

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import PathCollection  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402

from conftest import SCENES  # noqa: E402
from raykit.camera import image_plane_points, pixel_points, rays_through  # noqa: E402
from raykit.cli import main  # noqa: E402
from raykit.diagrams import distributed, math_figures  # noqa: E402
from raykit.diagrams.camera import camera_diagram, camera_diagrams, coarse  # noqa: E402
from raykit.diagrams.rays import chosen_pixels, ray_diagram  # noqa: E402
from raykit.diagrams.views import view_for  # noqa: E402
from raykit.engine.noise import Dimensions, PixelSamples  # noqa: E402
from raykit.io.images import NOTEBOOK_DPI, figure_png  # noqa: E402
from raykit.io.legibility import legibility_problems, measuring, read_layout  # noqa: E402
from raykit.io.linescan_json import load_line_scene  # noqa: E402
from raykit.io.scene_json import (
    load_scene,  # noqa: E402
    scene_from_dict,  # noqa: E402
)
from raykit.linescan.diagrams import ray_diagram as linescan_rays  # noqa: E402
from raykit.rays import point_at  # noqa: E402
from raykit.render import cast, cast_pixels, render  # noqa: E402
from raykit.spheres import sphere_roots  # noqa: E402


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def _segments(figure, gid):
    found = [c for ax in figure.axes for c in ax.collections if c.get_gid() == gid]
    assert len(found) == 1
    segments = found[0].get_segments()
    return np.array(segments).reshape(-1, 2, np.shape(segments[0])[-1]) if segments else None


def test_cast_pixels_are_the_renderers_own_centre_rays():
    scene = load_scene(SCENES / "cutouts.json")
    rows, cols = chosen_pixels(scene.camera.width, scene.camera.height, every=17)
    _, _, hits = cast_pixels(scene, rows, cols)
    image = render(scene)
    assert np.array_equal(hits.index, image.object_index[rows, cols])
    assert np.array_equal(hits.t, image.t[rows, cols])


@pytest.mark.parametrize("view", ["top", "side"])
@pytest.mark.parametrize("name", ["classic", "cutouts", "orthographic", "wide_fov"])
def test_drawn_rays_end_at_the_renderers_hit_points_on_the_pixel_showing_that_object(name, view):
    scene = load_scene(SCENES / f"{name}.json")
    figure = ray_diagram(scene, view=view)
    rows, cols = chosen_pixels(scene.camera.width, scene.camera.height)
    origins, directions, hits = cast_pixels(scene, rows, cols)
    hit = hits.index >= 0
    shown = view_for(scene.camera, view)
    drawn = _segments(figure, "rays-hit")
    assert np.array_equal(drawn[:, 1], shown.project(point_at(origins, directions, hits.t))[hit])
    # the object each drawn ray ends on is the object the render shows at that pixel
    assert np.array_equal(render(scene).object_index[rows, cols][hit], hits.index[hit])


def test_3d_view_draws_the_same_hit_points_in_its_axes_order():
    scene = load_scene(SCENES / "classic.json")
    figure = ray_diagram(scene, view="3d", every=100)
    rows, cols = chosen_pixels(scene.camera.width, scene.camera.height, every=100)
    origins, directions, hits = cast_pixels(scene, rows, cols)
    ends = view_for(scene.camera, "3d").project(point_at(origins, directions, hits.t))
    (rays,) = [c for c in figure.axes[0].collections if c.get_gid() == "rays-hit"]
    drawn = np.asarray(rays._segments3d)  # mplot3d keeps the 3D segments here until drawn
    assert np.array_equal(drawn[:, 1], ends[hits.index >= 0])


def test_number_of_rays_drawn_every_kth_pixel_a_row_or_given_pixels():
    scene = load_scene(SCENES / "classic.json")  # 640 x 480

    def count(**kw):
        figure = ray_diagram(scene, view="top", **kw)
        return sum(
            len(c.get_segments())
            for c in figure.axes[0].collections
            if c.get_gid() in ("rays-hit", "rays-missed")
        )

    assert count(every=80) == 8 * 6
    assert count(every=64, row=240) == 10
    assert count(pixels=[(0, 0), (240, 320), (479, 639)]) == 3
    assert count() <= 64


def test_chosen_pixels_are_centred_in_the_image():
    rows, cols = chosen_pixels(9, 5, every=4)
    assert sorted(set(cols)) == [0, 4, 8] and sorted(set(rows)) == [0, 4]


def test_top_and_side_views_follow_the_camera_up_and_view_direction():
    camera = load_scene(SCENES / "classic.json").camera  # y up, looking along -z
    assert view_for(camera, "top").axes == (0, 2)
    assert view_for(camera, "side").axes == (2, 1)
    assert view_for(camera, "3d").axes == (0, 2, 1)
    assert view_for(camera, "front").axes == (0, 1)  # across and up, as the eye sees them
    with pytest.raises(ValueError):
        view_for(camera, "back")


def test_camera_diagram_draws_the_cameras_own_pixel_centres():
    camera = load_scene(SCENES / "classic.json").camera
    figure = camera_diagram(camera)
    grid = coarse(camera)
    assert (grid.width, grid.height) == (8, 6)
    centres = image_plane_points(grid, *pixel_points(8, range(6)))
    drawn = figure.axes[0].collections
    offsets = [np.asarray(c._offsets3d).T for c in drawn if hasattr(c, "_offsets3d")]
    view = view_for(camera, "3d")
    assert any(o.shape == (48, 3) and np.allclose(o, view.project(centres)) for o in offsets)
    # the image plane's centre is lookat, and the centre ray goes there
    _, d = rays_through(camera, np.array([camera.width / 2]), np.array([camera.height / 2]))
    assert np.allclose(np.cross(d[0], camera.lookat - camera.eye), 0, atol=1e-9)


@pytest.mark.parametrize("name", sorted(p.stem for p in SCENES.glob("*.json")))
def test_camera_diagram_labels_are_clear_of_each_other_and_of_the_lines(name):
    figure = camera_diagrams(load_scene(SCENES / f"{name}.json").camera)
    with measuring(figure) as layout:
        figure.canvas.draw()
    drawn = [t.text for t in layout.texts]
    for label in ("u", "v", "w", "up", "e", "lookat", "d"):
        assert drawn.count(label) == 2, label  # once in each of the two cameras
    assert not layout.problems, layout.problems


def test_sphere_cases_mark_the_roots_the_math_returns():
    figure = math_figures.sphere_cases()
    titles = [ax.get_title() for ax in figure.axes]
    assert titles == [
        "D = B² − 4AC < 0: no root: a miss",
        "D = B² − 4AC = 0: one root: grazes",
        "D = B² − 4AC > 0: two roots",
    ]
    t0, t1, _ = sphere_roots(np.array([[-2.6, 0.45]]), np.array([[1.0, 0.0]]), np.zeros(2), 1.0)
    labels = [t.get_text() for t in figure.axes[2].texts]
    assert f"t0 = {min(t0[0], t1[0]):.2f}" in labels and f"t1 = {max(t0[0], t1[0]):.2f}" in labels


def test_plane_sides_colours_each_point_by_the_side_plane_side_returns():
    figure = math_figures.plane_sides()
    ax = figure.axes[0]
    counts = {}
    for line in ax.lines:
        label = line.get_label()
        if label.startswith(("in front", "on:", "behind")):
            counts[label.split(":")[0]] = len(line.get_xdata())
    assert counts["on"] == 2  # the two points put exactly on the plane
    assert counts["in front"] + counts["behind"] == 40
    assert min(counts["in front"], counts["behind"]) > 5
    texts = [t.get_text() for t in figure.axes[1].texts]
    assert "n = (p - a) × (q - a)\n|n| = 3" in texts  # drawn at its own length, not 1


def test_diagram_command_writes_each_view(tmp_path, capsys):
    for view in ("3d", "top", "side", "camera"):
        out = tmp_path / f"{view}.png"
        assert (
            main(
                [
                    "diagram",
                    str(SCENES / "classic.json"),
                    "-o",
                    str(out),
                    "--view",
                    view,
                    "--rays",
                    "120",
                ]
            )
            == 0
        )
        assert out.stat().st_size > 10_000
    assert capsys.readouterr().out.count("wrote") == 4


def test_diagram_command_on_a_bad_scene_is_one_line_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text('{"camera": {}}')
    assert main(["diagram", str(bad), "-o", str(tmp_path / "d.png")]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not (tmp_path / "d.png").exists()


def test_lit_scene_diagram_draws_the_shadow_and_mirror_rays_shading_cast():
    from raykit.diagrams.rays import RecordingCaster
    from raykit.rays import point_at
    from raykit.render import secondary_caster
    from raykit.shading import shade

    scene = load_scene(SCENES / "mirror_balls.json")
    figure = ray_diagram(scene, view="top", every=40)
    rows, cols = chosen_pixels(scene.camera.width, scene.camera.height, every=40)
    origins, directions, hits = cast_pixels(scene, rows, cols)
    recorder = RecordingCaster(secondary_caster(scene))
    colors = shade(scene, recorder, origins, directions, hits)
    assert np.array_equal(colors, shade(scene, secondary_caster(scene), origins, directions, hits))
    paths = recorder.segments
    shown = view_for(scene.camera, "top")
    mirror = [p for p in paths if p.kind == "mirror"]
    assert mirror
    starts = np.vstack([p.origins for p in mirror])
    met = np.isfinite(np.concatenate([p.t for p in mirror]))
    assert met.any() and not met.all()
    assert np.array_equal(_segments(figure, "rays-mirror")[:, 0], shown.project(starts[met]))
    missed = _segments(figure, "rays-mirror-missed")  # dashed: they meet nothing
    assert np.array_equal(missed[:, 0], shown.project(starts[~met]))
    # each first mirror ray starts where a pixel's ray meets a mirror, ε off the surface
    on_mirror = scene.materials.mirror[hits.index].any(axis=1) & (hits.index >= 0)
    mirror_points = point_at(origins, directions, hits.t)[on_mirror]
    gaps = np.linalg.norm(mirror[0].origins[:, None] - mirror_points[None], axis=2).min(axis=1)
    assert len(mirror[0].origins) == on_mirror.sum() and np.all(gaps < 1e-9)
    shadow = [p for p in paths if p.kind == "shadow"]
    lit_drawn = _segments(figure, "rays-shadow")
    blocked = sum(int(p.blocked.sum()) for p in shadow)
    assert len(lit_drawn) + blocked == sum(len(p.t) for p in shadow) > 0


def test_unlit_scene_diagram_draws_no_secondary_rays():
    figure = ray_diagram(load_scene(SCENES / "classic.json"), view="top")
    gids = {c.get_gid() for ax in figure.axes for c in ax.collections}
    assert not gids & {"rays-shadow", "rays-blocked", "rays-mirror"}


def _lecture_figures():
    from raykit.diagrams.pinhole import pinhole_figure
    from raykit.io.linescan_json import load_line_scene
    from raykit.linescan.diagrams import paths_of_light, pixel_formulas, sweep_diagram
    from raykit.linescan.diagrams import ray_diagram as line_ray_diagram

    classic = load_scene(SCENES / "classic.json")
    slide = SCENES / "linescan" / "slide.json"
    return {
        "math_sphere_cases": math_figures.sphere_cases,
        "math_plane_hit": math_figures.plane_hit,
        "math_dot_projection": math_figures.dot_projection,
        "math_plane_sides": math_figures.plane_sides,
        "camera_diagrams": lambda: camera_diagrams(classic.camera),
        "pinhole_figure": lambda: pinhole_figure(classic),
        "rays_top": lambda: ray_diagram(classic, view="top"),
        "paths_of_light": lambda: paths_of_light(load_line_scene(slide), (3.0, 4.5)),
        "pixel_formulas": pixel_formulas,
        "line_scan_rays": lambda: line_ray_diagram(load_line_scene(slide)),
        "sweep": lambda: sweep_diagram(
            load_line_scene(SCENES / "linescan" / "passing_car.json"), scans=60
        ),
    }


@pytest.mark.parametrize("name", sorted(_lecture_figures()))
def test_lecture_figures_have_no_text_under_10_points(name):
    from matplotlib.text import Text

    figure = _lecture_figures()[name]()
    figure.canvas.draw()
    small = [
        (text.get_text(), text.get_fontsize())
        for text in figure.findobj(Text)
        if text.get_visible() and text.get_text().strip() and text.get_fontsize() < 10
    ]
    assert not small, f"{name}: {small}"


# lecture figures as a notebook shows them (raykit.io.images.show_figures_legibly) and as the
# site stores them (docs/make_images.py; tests/test_reproducible.py measures all of those): where
# the labels go depends on the size they are drawn at. Each of these had a label on a line
STORED_AS = {"notebook": {"dpi": NOTEBOOK_DPI, "bbox_inches": "tight"}, "docs": {}}
LABELS_ONCE_ON_LINES = [
    ("line_scan_rays", "notebook"),  # the fov_angle label's leader through "image line"
    ("line_scan_rays", "docs"),  # ... and through "D" (docs/images/slide_rays.png)
    ("camera_diagrams", "notebook"),  # a 3D gridline through "d", "fov_angle", "lookat"
    ("math_plane_sides", "notebook"),  # the 3D box's x axis under "a" and "p", gridlines
]


@pytest.mark.parametrize("name, stored", LABELS_ONCE_ON_LINES)
def test_lecture_figures_labels_are_clear_as_stored(name, stored):
    # no two texts on each other, none on a drawn line, nor on a 3D box's edge or gridline,
    # and no leader through another text (raykit.io.legibility)
    figure = _lecture_figures()[name]()
    layout = read_layout(figure_png(figure, **STORED_AS[stored]))
    assert not layout.problems, layout.problems


def test_a_leader_through_another_text_is_a_layout_problem():
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10)
    ax.text(5, 5, "in the way", ha="center", va="center")
    ax.annotate("far", (5, 1), xytext=(5, 9), ha="center", arrowprops={"arrowstyle": "-"})
    ax.annotate("beside", (1, 1), xytext=(1, 9), ha="center", arrowprops={"arrowstyle": "-"})
    layout = read_layout(figure_png(fig))
    assert layout.problems == ["the leader of 'far' runs through 'in the way'"]


@pytest.mark.parametrize("grid", [True, False])
def test_a_3d_box_edge_or_gridline_through_a_text_is_a_layout_problem(grid):
    fig = plt.figure(figsize=(4, 4))
    ax = fig.add_subplot(projection="3d")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.set_zlim(0, 1)
    ax.grid(grid)
    ax.figure.canvas.draw()  # where the box's x axis runs: its middle, in data coordinates
    (x0, y0), (x1, y1) = ax.xaxis.line.get_xydata()[[0, -1]]
    ax.text2D((x0 + x1) / 2, (y0 + y1) / 2, "on the edge", ha="center", va="center")
    ax.text(0.5, 0.5, 1.0, "on the grid", ha="center", va="center")
    problems = read_layout(figure_png(fig)).problems
    assert any(
        p.startswith("'on the edge' is drawn on a line of the 3D box's x axis") for p in problems
    )
    assert (
        any(p.startswith("'on the grid' is drawn on a line of the 3D box's") for p in problems)
        == grid
    )


def _drawn_points(ax):
    """Points in pixels along every line, marker and circle outline of a 2D axes."""
    from matplotlib.patches import Circle

    points = []
    for line in ax.lines:
        xy = ax.transData.transform(line.get_xydata())
        steps = np.linspace(0, 1, 60)[:, None]
        for start, end in zip(xy[:-1], xy[1:], strict=True):
            points.append(start + steps * (end - start))
        if line.get_marker() not in (None, "None", "", " "):
            radius = line.get_markersize() / 2 * ax.figure.dpi / 72
            for dx, dy in ((0, 0), (radius, 0), (-radius, 0), (0, radius), (0, -radius)):
                points.append(xy + [dx, dy])
    for patch in ax.patches:
        if isinstance(patch, Circle):
            path = patch.get_transform().transform_path(patch.get_path())
            points.append(path.interpolated(30).vertices)
    return np.vstack(points)


def _apart(a, b) -> bool:
    return a[0] >= b[2] or b[0] >= a[2] or a[1] >= b[3] or b[1] >= a[3]


@pytest.mark.parametrize("name", ["sphere_cases", "plane_hit", "dot_projection", "plane_sides"])
def test_math_figure_labels_touch_no_line_marker_circle_or_other_label(name):
    figure = getattr(math_figures, name)()
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    for ax in figure.axes:
        if ax.name == "3d":
            continue
        texts = [t for t in ax.texts if t.get_text().strip()]
        boxes = [t.get_window_extent(renderer).extents for t in texts]
        drawn = _drawn_points(ax)
        for text, (x0, y0, x1, y1) in zip(texts, boxes, strict=True):
            inside = (
                (drawn[:, 0] > x0) & (drawn[:, 0] < x1) & (drawn[:, 1] > y0) & (drawn[:, 1] < y1)
            )
            assert not inside.any(), f"{name}: {text.get_text()!r} lies on what is drawn"
        for i, (text, box) in enumerate(zip(texts, boxes, strict=True)):
            for other, other_box in zip(texts[i + 1 :], boxes[i + 1 :], strict=True):
                assert _apart(box, other_box), (
                    f"{name}: {text.get_text()!r} overlaps {other.get_text()!r}"
                )


# stage 5: one pixel's sampled rays (raykit.diagrams.distributed)


def _v2(name: str, **render_settings):
    data = json.loads((SCENES / name).read_text())
    data["camera"].update(width=40, height=30)
    data["render"].update(render_settings)
    return scene_from_dict(data, folder=SCENES)


def test_a_pixels_sample_diagram_draws_the_renderers_own_numbers_for_that_pixel():
    scene = _v2("soft_shadows.json", samples_per_pixel=9, seed=4)
    figure = distributed.pixel_samples_diagram(scene, 12, 20)
    numbers = PixelSamples(scene.sampling, Dimensions.of(scene).count)
    expected = np.vstack([numbers.of(np.array([12 * 40 + 20]), k)[:, 0:2] for k in range(9)])
    drawn = figure.axes[0].collections[0].get_offsets()
    assert np.array_equal(np.asarray(drawn), expected)


def test_the_shadow_ray_diagram_draws_one_shadow_ray_per_sample_to_the_light():
    scene = _v2("soft_shadows.json", samples_per_pixel=16)
    figure = distributed.shadow_rays_diagram(scene, 24, 12, view="side")
    assert len(_segments(figure, "rays-centre")) == 1
    reaching, blocked = (
        _segments(figure, f"rays-shadow-{kind}") for kind in ("reaching", "blocked")
    )
    assert sum(0 if s is None else len(s) for s in (reaching, blocked)) == 16
    light = scene.lights[0]  # the reaching rays end on the light's plane, y = 4.5
    assert reaching is not None and np.allclose(reaching[:, 1, 1], light.corner[1])


def test_the_penumbra_pixels_shadow_rays_cross_no_ball_where_they_are_drawn():
    """The notebook's shadow-ray diagram (notebook 07): a pixel of the penumbra, some rays
    blocked, some not, and none of those that reach the light drawn across a ball (a ray that
    passes beside one in space, drawn over it, looks as if it went through)."""
    data = json.loads((SCENES / "soft_shadows.json").read_text())
    data["camera"].update(width=160, height=120)  # as the notebook renders it
    scene = scene_from_dict(data, folder=SCENES)
    row, col = distributed.penumbra_pixel(scene)
    figure = distributed.shadow_rays_diagram(scene, row, col)
    reaching, blocked = (
        _segments(figure, f"rays-shadow-{kind}") for kind in ("reaching", "blocked")
    )
    assert reaching is not None and blocked is not None  # the penumbra: some of each
    balls = [p for p in figure.axes[0].patches if isinstance(p, Circle)]
    assert len(balls) == len(scene.spheres)
    for ball in balls:
        a, b = reaching[:, 0], reaching[:, 1]
        d = b - a
        along = np.clip(np.sum((ball.center - a) * d, axis=1) / np.sum(d * d, axis=1), 0, 1)
        nearest = a + along[:, None] * d
        assert (np.linalg.norm(nearest - ball.center, axis=1) > ball.radius).all()
    side = distributed.shadow_rays_diagram(scene, row, col, view="side")
    assert side is not None  # another view of the same pixel draws too


def test_the_moving_diagram_marks_each_hit_of_each_sample_at_its_time():
    scene = _v2("motion_blur.json", samples_per_pixel=16)
    figure = distributed.moving_rays_diagram(scene, [(17, 10), (17, 14)])
    marks = [c for c in figure.axes[0].collections if isinstance(c, PathCollection)]
    hits = sum(len(m.get_offsets()) for m in marks)
    expected = 0
    for row, col in [(17, 10), (17, 14)]:
        origins, directions, _, times = distributed.sample_rays(scene, row, col)
        assert len(np.unique(times)) == 16  # each ray its own time
        expected += int(np.count_nonzero(cast(scene, origins, directions, times=times).index >= 0))
    assert hits == expected > 0


# what docs/make_images.py does not draw (tests/test_reproducible.py measures those): every
# label clear of the lines, edges, markers and other labels, as measured while the figure is
# drawn into its PNG (raykit.io.legibility), and text a projector shows
CLEAR_LABEL_CASES = {
    "one camera": lambda: camera_diagram(load_scene(SCENES / "classic.json").camera),
    "rays 3d": lambda: ray_diagram(load_scene(SCENES / "classic.json"), view="3d", every=100),
    "conveyor rays": lambda: linescan_rays(load_line_scene(SCENES / "linescan/conveyor.json")),
    "pixel samples": lambda: distributed.pixel_samples_diagram(
        _v2("soft_shadows.json", samples_per_pixel=9, seed=4), 12, 20
    ),
    "shadow rays": lambda: distributed.shadow_rays_diagram(
        _v2("soft_shadows.json", samples_per_pixel=16), 24, 12
    ),
    "lens rays": lambda: distributed.lens_rays_diagram(
        _v2("depth_of_field.json", samples_per_pixel=16), 15, 20
    ),
    "glossy rays": lambda: distributed.glossy_rays_diagram(
        _v2("glossy.json", samples_per_pixel=16), 15, 12
    ),
    "moving rays": lambda: distributed.moving_rays_diagram(
        _v2("motion_blur.json", samples_per_pixel=16), [(17, 10), (17, 14)]
    ),
}


@pytest.mark.parametrize("case", sorted(CLEAR_LABEL_CASES))
def test_diagram_labels_are_clear(case):
    layout = read_layout(figure_png(CLEAR_LABEL_CASES[case]()))
    assert not layout.problems, layout.problems
    assert not legibility_problems(*layout.size, layout.smallest_text_px)


# log axes over measured ranges: a fraction of a decade to a few, at a few offsets (notebook 05's
# time against error spans about 1.7 decades of time and 0.9 of error, run to run more or less)
LOG_RANGES = [(0.0125, 0.7, 0.042, 0.0048), (0.3, 0.45, 2.0, 30.0), (0.002, 0.9, 0.06, 0.011)]
LOG_RANGES += [(3e-4, 2e-3, 0.5, 0.7), (0.05, 90.0, 1.5, 1.9)]


@pytest.mark.parametrize("ranges", LOG_RANGES, ids=lambda r: f"{r[0]:g}-{r[1]:g}")
def test_log_axes_tick_labels_keep_apart_whatever_the_range(ranges):
    from raykit.diagrams.labels import decade_ticks

    x0, x1, y0, y1 = ranges
    # as small as a figure fitted to the projector gets (its text a fortieth of its height)
    fig, ax = plt.subplots(figsize=(3.4, 2.8), layout="constrained")
    ax.loglog(np.geomspace(x0, x1, 4), np.geomspace(y0, y1, 4), "o-", label="a run")
    ax.set_xlabel("render time (s)")
    ax.set_ylabel("RMS error")
    fig.legend(loc="outside lower center")
    decade_ticks(ax)
    with measuring(fig) as layout:
        fig.savefig(io.BytesIO(), format="rgba", dpi=100)
    assert not layout.problems, layout.problems
    for axis, (low, high) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        shown = [
            t.get_text()
            for t, value in zip(axis.get_ticklabels(), axis.get_ticklocs(), strict=True)
            if t.get_text() and low <= value <= high
        ]
        assert len(shown) >= 2, shown
        assert all(t.endswith("}}$") and "times" not in t for t in shown), shown  # 10^k only

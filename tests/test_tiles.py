"""Skipping hidden objects changes no pixel; the screen bounds are conservative."""

import numpy as np
import pytest

from conftest import SCENES, random_scene, write_texture
from raykit.engine.screen_bounds import billboard_bounds, object_bounds, sphere_bounds
from raykit.engine.tiles import CROWDED, regions
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.render import render
from raykit.spheres import Sphere

EXAMPLES = sorted(SCENES.glob("*.json")) + sorted(
    (SCENES.parent / "grading/hidden-scenes").glob("*.json")
)


def _same(a, b) -> bool:
    return (
        np.array_equal(a.rgb, b.rgb)
        and np.array_equal(a.object_index, b.object_index)
        and np.array_equal(a.t, b.t)
    )


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
@pytest.mark.parametrize("samples", [1, pytest.param(2, marks=pytest.mark.slow)])
def test_skipping_changes_no_pixel_on_the_example_scenes(path, samples):
    scene = load_scene(path)
    if samples > 1 and scene.distributed:
        pytest.skip("a distributed scene takes render.samples_per_pixel, not the n x n grid")
    assert _same(render(scene, samples, skip_hidden=False), render(scene, samples))


def test_skipping_changes_no_pixel_on_random_scenes(tmp_path):
    rng = np.random.default_rng(99)
    write_texture(tmp_path, "noise.png", rng.integers(0, 256, size=(5, 7, 4)))
    for _ in range(60):
        scene = scene_from_dict(random_scene(rng, "noise.png"), folder=tmp_path)
        assert _same(render(scene, skip_hidden=False), render(scene))


def test_crowded_tiles_pair_rays_with_objects_and_change_no_pixel(tmp_path):
    """Scenes of 20-60 objects, textured billboards with holes among them, so that most tiles
    hold CROWDED objects or more and go through ray-object pairs (raykit.engine.pairs)."""
    rng = np.random.default_rng(31)
    write_texture(tmp_path, "noise.png", rng.integers(0, 256, size=(5, 7, 4)))
    crowded = 0
    for _ in range(8):
        data = random_scene(rng, "noise.png")
        for _ in range(int(rng.integers(20, 50))):
            data["spheres"].append(
                {
                    "center": rng.uniform(-4, 4, 3).tolist(),
                    "radius": float(rng.uniform(0.1, 1)),
                    "color": rng.uniform(0, 1, 3).tolist(),
                }
            )
        for _ in range(int(rng.integers(2, 10))):
            ul = rng.uniform(-4, 4, 3)
            data["billboards"].append(
                {
                    "upper_left": ul.tolist(),
                    "lower_left": (ul + rng.uniform(-3, 3, 3)).tolist(),
                    "upper_right": (ul + rng.uniform(-3, 3, 3)).tolist(),
                    "image": "noise.png",
                }
            )
        scene = scene_from_dict(data, folder=tmp_path)
        crowded += sum(len(r.index_of) - 1 >= CROWDED for r in regions(scene))
        for samples in (1, 2):
            assert _same(render(scene, samples, skip_hidden=False), render(scene, samples))
    assert crowded > 0


def test_rays_are_made_only_where_some_object_may_be_seen(monkeypatch):
    """A ball that fills a few hundred of 64,000 pixels: only the image points its screen
    rectangle holds get a ray; every other pixel is background without one, as it would be
    with its ray. Lit too: shading runs only on the rays made."""
    import raykit.engine.regions

    made = []
    real = raykit.engine.regions.rays_through

    def counting(camera, x, y):
        made.append(len(x))
        return real(camera, x, y)

    scene = scene_from_dict(
        {
            "camera": {
                "eye": [0, 0, 0],
                "lookat": [0, 0, -1],
                "up": [0, 1, 0],
                "fov_angle": 60,
                "width": 320,
                "height": 200,
            },
            "spheres": [{"center": [0.3, 0.1, -5], "radius": 0.2, "color": [1, 0, 0]}],
            "lights": [{"type": "directional", "direction": [0, 0, -1]}],
        }
    )
    full = render(scene, skip_hidden=False)
    monkeypatch.setattr(raykit.engine.regions, "rays_through", counting)
    skipping = render(scene)
    assert _same(full, skipping)
    ball = int((full.object_index == 0).sum())
    assert 0 < ball <= sum(made) < 2 * ball + 200, (ball, sum(made))


def _random_regions(rng, count: int = 40):
    """Tiles of 1-64 pixels a side with 30 screen rectangles each: inside, across and outside
    the tile, a third with edges through pixel centres, every seventh NaN (never visible)."""
    from raykit.engine.tiles import Region

    for _ in range(count):
        rows, cols = range(64, 64 + rng.integers(1, 65)), range(128, 128 + rng.integers(1, 65))
        corners = rng.uniform(40, 220, size=(30, 2, 2))
        corners[::3] = np.round(corners[::3]) + 0.5
        bounds = np.column_stack(
            [corners[:, 0].min(1), corners[:, 0].max(1), corners[:, 1].min(1), corners[:, 1].max(1)]
        )
        bounds[::7] = np.nan
        yield Region(rows, cols, None, None, None, bounds)


def test_pairs_on_the_pixel_grid_are_the_pairs_of_the_rectangle_table():
    """Region.pairs_on_grid finds by binary search the same (object, point) pairs, in the same
    order, as the (K, N) table of Region.holding, at several sample offsets."""
    from raykit.camera import region_points

    for region in _random_regions(np.random.default_rng(5)):
        for a, b in [(0.5, 0.5), (1 / 6, 5 / 6), (0.125, 0.875)]:
            x, y = region_points(region.rows, region.cols, a, b)
            expected = np.nonzero(region.holding(x, y))
            got = region.pairs_on_grid(a, b)
            assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])


def test_pairs_at_any_points_are_the_pairs_of_the_rectangle_table():
    """Region.pairs_at finds the same (object, point) pairs as the (K, N) table of
    Region.holding, grouped by object, for scattered points as adaptive sampling casts them,
    some on pixel corners and some on rectangle edges."""
    rng = np.random.default_rng(6)
    for region in _random_regions(rng):
        rows, cols, bounds = region.rows, region.cols, region.bounds
        x = rng.uniform(cols.start, cols.stop, 400)
        y = rng.uniform(rows.start, rows.stop, 400)
        x[:50], y[:50] = np.floor(x[:50]), np.floor(y[:50])  # pixel corners
        visible = bounds[~np.isnan(bounds[:, 0])]  # points on their edges:
        x[50:100] = np.clip(rng.choice(visible[:, 1], 50), cols.start, cols.stop - 0.01)
        y[100:150] = np.clip(rng.choice(visible[:, 2], 50), rows.start, rows.stop - 0.01)
        expected = np.nonzero(region.holding(x, y))
        which, point = region.pairs_at(x, y)
        assert np.all(np.diff(which) >= 0)
        order = np.lexsort((point, which))
        assert np.array_equal(which[order], expected[0])
        assert np.array_equal(point[order], expected[1])


def test_bounds_hold_every_pixel_where_the_object_is_seen(tmp_path):
    rng = np.random.default_rng(5)
    write_texture(tmp_path, "noise.png", rng.integers(0, 256, size=(5, 7, 4)))
    for _ in range(40):
        scene = scene_from_dict(random_scene(rng, "noise.png"), folder=tmp_path)
        index = render(scene, skip_hidden=False).object_index
        bounds = object_bounds(scene.camera, scene.objects)
        for k in range(len(scene.objects)):
            rows, cols = np.nonzero(index == k)
            if len(rows) == 0:
                continue
            x0, x1, y0, y1 = bounds[k]
            assert x0 <= cols.min() + 0.5 and cols.max() + 0.5 <= x1
            assert y0 <= rows.min() + 0.5 and rows.max() + 0.5 <= y1


def test_objects_behind_the_eye_have_no_bounds_and_ones_around_it_the_whole_image():
    camera = load_scene(SCENES / "classic.json").camera  # eye (0, 3, 10) looking along -z
    behind = Sphere(np.array([0.0, 3.0, 14.0]), 1.0, np.ones(3))
    around = Sphere(np.array([0.0, 3.0, 10.5]), 1.0, np.ones(3))
    assert sphere_bounds(camera, behind) is None
    assert sphere_bounds(camera, around) == (0.0, 640.0, 0.0, 480.0)
    ground = load_scene(SCENES / "classic.json").billboards[0]
    x0, x1, y0, y1 = billboard_bounds(camera, ground)
    assert x0 == 0 and x1 == 640 and y1 == 480 and 100 < y0 < 300  # below the horizon


@pytest.mark.parametrize("projection", ["perspective", "orthographic"])
def test_the_billboards_bounds_at_once_are_each_ones_own(projection):
    """billboards_bounds computes every billboard's rectangle in one pass: no row depends on
    another's, whether seen, behind the eye, around it or off the image."""
    from dataclasses import replace

    from raykit.billboards import Billboard
    from raykit.engine.screen_bounds import billboards_bounds

    camera = replace(load_scene(SCENES / "classic.json").camera, projection=projection)
    rng = np.random.default_rng(31)
    corners = [rng.normal(size=3) * 6 for _ in range(12)] + [np.array([0.0, 3.0, 14.0])]
    corners += [np.array([0.0, 3.0, 9.9]), np.array([500.0, 3.0, 0.0])]  # behind, around, off
    boards = [
        Billboard(c, c + rng.normal(size=3), c + rng.normal(size=3), np.ones(3)) for c in corners
    ]
    together = billboards_bounds(camera, boards)
    for board, row in zip(boards, together, strict=True):
        alone = billboard_bounds(camera, board)
        assert (alone is None and np.isnan(row).all()) or tuple(row) == alone
    assert np.isnan(together).all(axis=1).any() and np.isfinite(together).all(axis=1).any()


def test_a_sphere_bound_is_tight_to_a_pixel():
    camera = load_scene(SCENES / "classic.json").camera
    sphere = load_scene(SCENES / "classic.json").spheres[0]  # the red ball, fully in view
    index = render(load_scene(SCENES / "classic.json"), skip_hidden=False).object_index
    rows, cols = np.nonzero(index == 0)
    x0, x1, y0, y1 = sphere_bounds(camera, sphere)
    assert cols.min() - x0 < 2.5 and x1 - cols.max() < 3.5


@pytest.mark.parametrize("projection", ["perspective", "orthographic"])
def test_no_ray_beyond_a_sphere_bound_hits_it_even_a_hair_beyond_the_silhouette(projection):
    """The margin is a thousandth of a pixel (raykit.engine.screen_bounds.MARGIN): every image
    point just outside a rectangle, from a hair to half a pixel beyond it, has a ray that misses
    the sphere, for spheres near and far, large and far smaller than a pixel, at 1e6 too."""
    from dataclasses import replace

    from raykit.camera import rays_through
    from raykit.engine.screen_bounds import MARGIN
    from raykit.spheres import hit_sphere

    rng = np.random.default_rng(21)
    camera = load_scene(SCENES / "classic.json").camera
    checked = 0
    for trial in range(60):
        shift = 1e6 if trial % 3 == 0 else 0.0
        view = replace(
            camera,
            projection=projection,
            eye=camera.eye + shift,
            lookat=camera.lookat + shift,
        )
        distance = 10 ** rng.uniform(0, 4)
        radius = distance * 10 ** rng.uniform(-5, -0.5)  # from a hundredth of a pixel up
        u, v, w = view.frame
        across = rng.uniform(-0.3, 0.3, 2) * distance
        center = view.eye - distance * w + across[0] * u + across[1] * v
        bound = sphere_bounds(view, Sphere(center, radius, np.ones(3)))
        if bound is None:
            continue
        x0, x1, y0, y1 = bound
        # points beyond each edge, from 1e-9 px to half a pixel out, and along the whole edge
        beyond = 10 ** rng.uniform(-9, np.log10(0.5), 4000)
        along = rng.uniform(0, 1, 4000)
        xs = np.concatenate([x0 - beyond[:1000], x1 + beyond[1000:2000],
                             x0 + along[2000:] * (x1 - x0)])  # fmt: skip
        ys = np.concatenate([y0 + along[:2000] * (y1 - y0), y0 - beyond[2000:3000],
                             y1 + beyond[3000:]])  # fmt: skip
        inside = (xs > 0) & (xs < view.width) & (ys > 0) & (ys < view.height)
        origins, directions = rays_through(view, xs[inside], ys[inside])
        hits = hit_sphere(origins, directions, np.asarray(center), radius)
        assert not np.isfinite(hits).any(), (trial, MARGIN)
        checked += inside.sum()
    assert checked > 50_000

import json
import math

import numpy as np
import pytest
from PIL import Image

from raykit.io.linescan_json import line_scene_from_dict
from raykit.linescan.camera import (
    LineCamera,
    line_rays,
    pixel_positions,
    pixel_x,
    slide_pixel_positions,
)
from raykit.linescan.objects import Ball, Billboard, hit_segment
from raykit.linescan.scan import scan, sweep
from raykit.linescan.scene import LineScene


def camera(**kw) -> LineCamera:
    args = dict(e=np.array([0.0, 0.0]), w=np.array([1.0, 0.0]), fov_angle=90.0, pixels=8)
    args.update(kw)
    return LineCamera(**args)


def ball(center, radius, color=(1, 0, 0), velocity=(0, 0)) -> Ball:
    return Ball(np.array(center, float), radius, np.array(color, float), np.array(velocity, float))


def test_distance_to_the_image_line_is_one_at_fov_90():
    assert camera(fov_angle=90).D == pytest.approx(1.0)
    assert camera(fov_angle=60).D == pytest.approx(math.sqrt(3))


def test_pixel_centres_are_symmetric_about_the_axis_and_half_a_pixel_in():
    x = pixel_x(8)
    assert np.allclose(x, -x[::-1])
    assert x[0] == pytest.approx(-1 + 1 / 8) and x[-1] == pytest.approx(1 - 1 / 8)
    assert np.allclose(pixel_x(3, samples=2), [-5 / 6, -3 / 6, -1 / 6, 1 / 6, 3 / 6, 5 / 6])


def test_u_is_w_turned_a_quarter_to_the_left_and_w_need_not_be_unit():
    u, w = camera(w=np.array([0.0, 3.0])).frame
    assert np.allclose(w, [0, 1]) and np.allclose(u, [-1, 0])


def test_pixel_positions_are_e_plus_x_u_plus_D_w_and_rays_go_through_them():
    cam = camera(e=np.array([2.0, 1.0]), w=np.array([1.0, 1.0]), fov_angle=50, pixels=5)
    u, w = cam.frame
    p = pixel_positions(cam)
    assert np.allclose(p, cam.e + pixel_x(5)[:, None] * u + cam.D * w)
    origins, directions = line_rays(cam)
    assert np.allclose(origins, cam.e)
    assert np.allclose(np.linalg.norm(directions, axis=1), 1)
    to_pixel = (p - cam.e) / np.linalg.norm(p - cam.e, axis=1)[:, None]
    assert np.allclose(directions, to_pixel)


def test_edge_of_the_image_line_is_seen_at_half_the_fov():
    cam = camera(fov_angle=70)
    end = cam.e + cam.D * cam.frame[1] + cam.frame[0]
    assert math.degrees(math.atan2(end[1], end[0])) == pytest.approx(35)


def test_orthographic_rays_are_parallel_with_origins_along_a_line_through_e():
    cam = camera(projection="orthographic", width=4.0, pixels=4)
    origins, directions = line_rays(cam)
    assert np.allclose(directions, [1, 0])
    assert np.allclose(origins[:, 0], 0) and np.allclose(origins[:, 1], [-1.5, -0.5, 0.5, 1.5])


def test_ray_through_a_circle_centre_hits_at_distance_minus_radius():
    scene = LineScene(camera(pixels=5, e=np.array([1.0, 2.0])), balls=(ball([7, 2], 1.5),))
    taken = scan(scene)
    assert taken.t[2] == pytest.approx(6.0 - 1.5)
    assert np.allclose(taken.hit_points[2], [5.5, 2.0])


def test_pixel_zero_is_on_the_right_of_the_view():
    # looking along +x, "right" is -y: a ball there shows in the low pixel indices
    scene = LineScene(camera(pixels=8), balls=(ball([5, -3], 1),))
    assert set(np.flatnonzero(scan(scene).index == 0)) <= {0, 1, 2, 3}


def _texture(tmp_path, rgba_row):
    Image.fromarray(np.array([rgba_row], np.uint8), "RGBA").save(tmp_path / "row.png")
    return "row.png"


def test_segment_texel_index_follows_the_parameter_from_start(tmp_path):
    name = _texture(
        tmp_path, [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255, 255, 0, 255]]
    )
    data = {
        "camera": {"e": [0, 0], "w": [1, 0], "fov_angle": 90, "pixels": 1},
        "billboards": [{"start": [3, -2], "end": [3, 2], "image": name}],
    }
    scene = line_scene_from_dict(data, folder=tmp_path)
    board = scene.billboards[0]
    t, s = hit_segment(
        np.array([[0.0, 0.0], [0.0, -1.9]]), np.array([[1.0, 0.0], [1.0, 0.0]]), board
    )
    assert np.allclose(t, 3) and np.allclose(s, [0.5, 0.025])
    assert np.allclose(scan(scene).colors[0], [0, 0, 1])  # s = 0.5 -> texel floor(2) = 2


def test_transparent_texels_let_the_ray_go_on(tmp_path):
    name = _texture(tmp_path, [[0, 0, 0, 0], [0, 0, 0, 127]])
    data = {
        "camera": {"e": [0, 0], "w": [1, 0], "fov_angle": 90, "pixels": 4},
        "balls": [{"center": [9, 0], "radius": 7, "color": [1, 0, 0]}],
        "billboards": [{"start": [2, -5], "end": [2, 5], "image": name}],
    }
    assert (scan(line_scene_from_dict(data, folder=tmp_path)).index == 0).all()


def test_nearest_hit_wins_and_exact_ties_go_to_the_first_listed():
    near, far = ball([4, 0], 1, (1, 0, 0)), ball([8, 0], 3, (0, 1, 0))
    assert scan(LineScene(camera(pixels=3), balls=(far, near))).index[1] == 1
    twin = ball([4, 0], 1, (0, 0, 1))
    assert scan(LineScene(camera(pixels=3), balls=(near, twin))).index[1] == 0


def test_behind_the_eye_is_not_seen_and_inside_a_ball_sees_it_everywhere():
    assert (scan(LineScene(camera(), balls=(ball([-4, 0], 1),))).index == -1).all()
    assert (scan(LineScene(camera(), balls=(ball([0.2, 0], 2),))).index == 0).all()


def test_samples_average_the_colours_in_a_pixel():
    # orthographic, one pixel of width 2: a wall covering y > 0 only fills half the samples
    wall = Billboard(np.array([3.0, 0.0]), np.array([3.0, 9.0]), color=np.array([1.0, 1, 1]))
    scene = LineScene(camera(pixels=1, projection="orthographic"), billboards=(wall,))
    assert np.allclose(scan(scene, samples=4).colors[0], 0.5)


def test_sweep_width_in_scans_of_a_moving_circle_matches_the_hand_count():
    # orthographic camera looking up (+y); a ball crosses at speed v along x. Pixel i, at x_i,
    # sees it on the scans m with |c0 + m v - x_i| < r: about 2r/v scans.
    r, v, c0, pixels = 0.5, 0.03, -2.013, 9  # no scan exactly tangent to a ray
    cam = camera(
        e=np.array([0.0, -5.0]),
        w=np.array([0.0, 1.0]),
        projection="orthographic",
        width=3.0,
        pixels=pixels,
    )
    scene = LineScene(cam, balls=(ball([c0, 0], r, velocity=(v, 0)),), scans=200)
    seen = sweep(scene).index == 0
    x = line_rays(cam)[0][:, 0]  # where each pixel's ray crosses the road
    for i in range(pixels):
        m = np.arange(200)
        expected = np.abs(c0 + m * v - x[i]) < r
        assert np.array_equal(seen[:, i], expected), i
        assert abs(expected.sum() - 2 * r / v) <= 1
    # pixel 0 is on the right (+x): the ball, moving +x, reaches it last
    assert np.flatnonzero(seen[:, 0])[0] > np.flatnonzero(seen[:, -1])[0]


def test_moving_camera_is_the_same_as_the_world_moving_the_other_way():
    b = ball([5, 0], 1, velocity=(0, 0))
    moving_camera = LineScene(
        camera(pixels=16), balls=(b,), camera_velocity=np.array([0, 0.1]), scans=30
    )
    moving_world = LineScene(
        camera(pixels=16), balls=(ball([5, 0], 1, velocity=(0, -0.1)),), scans=30
    )
    assert np.array_equal(sweep(moving_camera).index, sweep(moving_world).index)


# -- an independent computation on random scenes -----------------------------------------------


def _independent_scan(data: dict) -> tuple[list[int], list]:
    """Scalar, from the spec text: rays p_i - e, circles by closest approach, segments by
    solving e + t d = a + s (b - a) with Cramer's rule."""
    cam = data["camera"]
    ex, ey = cam["e"]
    wx, wy = cam["w"]
    n = math.hypot(wx, wy)
    wx, wy = wx / n, wy / n
    ux, uy = -wy, wx
    D = 1 / math.tan(math.radians(cam["fov_angle"]) / 2)
    index, points = [], []
    for i in range(cam["pixels"]):
        x = -1 + (i + 0.5) * 2 / cam["pixels"]
        dx, dy = x * ux + D * wx, x * uy + D * wy
        norm = math.hypot(dx, dy)
        dx, dy = dx / norm, dy / norm
        best, best_t = -1, math.inf
        objects = [("ball", b) for b in data.get("balls", [])]
        objects += [("board", b) for b in data.get("billboards", [])]
        for k, (kind, obj) in enumerate(objects):
            t = None
            if kind == "ball":
                cx, cy = obj["center"][0] - ex, obj["center"][1] - ey
                tca = cx * dx + cy * dy
                h2 = obj["radius"] ** 2 - ((cx - tca * dx) ** 2 + (cy - tca * dy) ** 2)
                if h2 >= 0:
                    for cand in (tca - math.sqrt(h2), tca + math.sqrt(h2)):
                        if cand > 0:
                            t = cand
                            break
            else:
                (ax, ay), (bx, by) = obj["start"], obj["end"]
                sx, sy = bx - ax, by - ay
                det = dx * (-sy) - dy * (-sx)
                if det != 0:
                    rx, ry = ax - ex, ay - ey
                    cand = (rx * (-sy) - ry * (-sx)) / det
                    s = (dx * ry - dy * rx) / det
                    if cand > 0 and 0 <= s <= 1:
                        t = cand
            if t is not None and t < best_t:
                best, best_t = k, t
        index.append(best)
        points.append((ex + best_t * dx, ey + best_t * dy) if best >= 0 else None)
    return index, points


def test_hits_and_colours_agree_with_an_independent_computation_on_random_scenes():
    rng = np.random.default_rng(11)
    agree = total = 0
    for _ in range(60):
        data = {
            "camera": {
                "e": rng.uniform(-3, 3, 2).tolist(),
                "w": rng.normal(size=2).tolist(),
                "fov_angle": float(rng.uniform(5, 175)),
                "pixels": int(rng.integers(1, 60)),
            },
            "balls": [
                {
                    "center": rng.uniform(-8, 8, 2).tolist(),
                    "radius": float(rng.uniform(0.1, 3)),
                    "color": rng.uniform(0, 1, 3).tolist(),
                }
                for _ in range(rng.integers(0, 6))
            ],
            "billboards": [
                {
                    "start": rng.uniform(-8, 8, 2).tolist(),
                    "end": rng.uniform(-8, 8, 2).tolist(),
                    "color": rng.uniform(0, 1, 3).tolist(),
                }
                for _ in range(rng.integers(0, 6))
            ],
        }
        scene = line_scene_from_dict(data)
        taken = scan(scene)
        index, points = _independent_scan(data)
        agree += int((taken.index == index).sum())
        total += len(index)
        for i, k in enumerate(index):
            if k >= 0 and taken.index[i] == k:
                assert np.allclose(taken.hit_points[i], points[i], atol=1e-9)
                assert np.allclose(taken.colors[i], scene.objects[k].color)
    assert agree == total


def test_slides_second_pixel_formula_gives_one_position_too_many_and_ends_on_the_edges():
    u = slide_pixel_positions(8)
    assert u.tolist() == [-1.0, -0.75, -0.5, -0.25, 0.0, 0.25, 0.5, 0.75, 1.0]  # 9, not 8
    assert len(slide_pixel_positions(640)) == 641
    assert len(slide_pixel_positions(7)) == 7  # odd: i = 0, ±1, ±2, ±3
    # for even N, every position is a pixel edge: half a pixel from the nearest centre x_i
    centres = pixel_x(640)
    gap = np.abs(slide_pixel_positions(640)[:, None] - centres[None]).min(axis=1)
    assert np.allclose(gap, 1.0 / 640)


# -- rules docs/linescan-format.md settles ----------------------------------------------------


def _wall(start, end) -> Billboard:
    return Billboard(np.array(start, float), np.array(end, float), color=np.array([1.0, 1, 1]))


def test_a_segment_along_a_ray_is_missed_and_one_touched_at_an_end_is_hit():
    origins, directions = np.array([[0.0, 0.0]]), np.array([[1.0, 0.0]])
    along = _wall([2, 0], [5, 0])  # the ray runs inside the segment: parallel, a miss
    assert hit_segment(origins, directions, along)[0][0] == np.inf
    for start, end in (([3, 0], [3, 2]), ([3, -2], [3, 0])):  # touched exactly at s = 0 or 1
        t, s = hit_segment(origins, directions, _wall(start, end))
        assert t[0] == 3 and s[0] in (0, 1)
    # a ray tangent to a ball (discriminant exactly 0) hits it
    assert scan(LineScene(camera(pixels=1), balls=(ball([5, 1], 1),))).index[0] == 0


def test_samples_sit_at_the_centres_of_equal_parts_of_the_pixel():
    # n samples of pixel i: x = -1 + (i + (k + 0.5)/n)·2/N, no jitter, the centre kept for odd n
    assert pixel_x(2, 2).tolist() == [-0.75, -0.25, 0.25, 0.75]
    assert pixel_x(1, 3).tolist() == pytest.approx([-2 / 3, 0, 2 / 3])


def test_strip_column_0_is_pixel_0_on_the_viewers_right(tmp_path):
    from raykit.cli import main

    # looking along +x, a red ball on the right (-y) and a blue one on the left (+y)
    data = {
        "camera": {"e": [0, 0], "w": [1, 0], "fov_angle": 90, "pixels": 4},
        "balls": [
            {"center": [5, -3], "radius": 1, "color": [1, 0, 0]},
            {"center": [5, 3], "radius": 1, "color": [0, 0, 1]},
        ],
    }
    path = tmp_path / "two.json"
    path.write_text(json.dumps(data))
    assert main(["scan", str(path), "-o", str(tmp_path / "strip.png")]) == 0
    strip = np.asarray(Image.open(tmp_path / "strip.png"))[0]
    assert strip[0].tolist() == [255, 0, 0] and strip[-1].tolist() == [0, 0, 255]

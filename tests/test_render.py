import math
from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENES, random_scene, scene_dict, write_texture
from independent_tracer import trace_object_index
from raykit.io.images import quantize
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.render import render


def rendered(scene: dict, folder=".", samples: int = 1):
    return render(scene_from_dict(scene, folder=folder), samples=samples)


def test_silhouette_radius_in_pixels_matches_the_projection_formula():
    # a sphere of radius r at distance L on the axis subtends asin(r/L); on the image plane
    # (distance d) that is a circle of radius d·tan(asin(r/L)), in pixels / (Hp/height)
    r, L, fov, size = 1.0, 7.0, 30.0, 101
    scene = scene_dict(
        camera={
            "eye": [0, 0, L],
            "lookat": [0, 0, 0],
            "up": [0, 1, 0],
            "fov_angle": fov,
            "width": size,
            "height": size,
        }
    )
    index = rendered(scene).object_index
    plane_h = 2 * L * math.tan(math.radians(fov) / 2)
    radius_px = L * math.tan(math.asin(r / L)) / (plane_h / size)
    yy, xx = np.mgrid[0:size, 0:size] + 0.5
    from_centre = np.hypot(xx - size / 2, yy - size / 2)
    assert (index[from_centre < radius_px - 0.01] == 0).all()
    assert (index[from_centre > radius_px + 0.01] == -1).all()
    assert 20 < radius_px < 40  # big enough that the rings above hold many pixels


def test_centre_pixel_t_is_distance_to_the_surface():
    scene = scene_dict()
    scene["camera"].update(width=33, height=33)
    assert rendered(scene).t[16, 16] == pytest.approx(4.0)


def test_world_right_and_up_appear_right_and_at_the_top():
    scene = scene_dict(
        spheres=[
            {"center": [1.5, 0, 0], "radius": 0.4, "color": [1, 0, 0]},
            {"center": [0, 1.2, 0], "radius": 0.4, "color": [0, 1, 0]},
        ]
    )
    index = rendered(scene).object_index
    rows, cols = np.nonzero(index == 0)
    assert cols.min() > 16
    rows, cols = np.nonzero(index == 1)
    assert rows.max() < 12


def test_object_behind_the_eye_is_not_seen_and_camera_inside_a_sphere_sees_it_everywhere():
    behind = scene_dict(spheres=[{"center": [0, 0, 9], "radius": 1, "color": [1, 0, 0]}])
    assert (rendered(behind).object_index == -1).all()
    inside = scene_dict(spheres=[{"center": [0, 0, 5], "radius": 2, "color": [1, 0, 0]}])
    assert (rendered(inside).object_index == 0).all()


def test_hit_at_t_zero_is_a_miss():
    # orthographic rays start on the plane through the eye; a billboard there is not hit
    scene = scene_dict(spheres=[])
    scene["camera"]["projection"] = "orthographic"
    scene["billboards"] = [
        {
            "upper_left": [-9, 9, 5],
            "lower_left": [-9, -9, 5],
            "upper_right": [9, 9, 5],
            "color": [1, 1, 1],
        }
    ]
    assert (rendered(scene).object_index == -1).all()


def test_exact_ties_go_to_the_object_listed_first():
    twins = [
        {"center": [0, 0, 0], "radius": 1, "color": [1, 0, 0]},
        {"center": [0, 0, 0], "radius": 1, "color": [0, 0, 1]},
    ]
    result = rendered(scene_dict(spheres=twins))
    assert set(np.unique(result.object_index)) == {-1, 0}
    boards = [
        {
            "upper_left": [-1, 1, 0],
            "lower_left": [-1, -1, 0],
            "upper_right": [1, 1, 0],
            "color": [c, 0, 0],
        }
        for c in (1, 0.5)
    ]
    result = rendered(scene_dict(spheres=[], billboards=boards))
    assert set(np.unique(result.object_index)) == {-1, 0}


def test_background_colour_on_a_miss_and_black_by_default():
    assert (rendered(scene_dict(spheres=[])).rgb == 0).all()
    result = rendered(scene_dict(spheres=[], background=[0.2, 0.4, 0.6]))
    assert np.allclose(result.rgb, [0.2, 0.4, 0.6])


def _facing_board(image, z=0.0, flip=False):
    """A 2 x 2 billboard at z, upper-left at (-1, 1); with flip, its corners mirrored in x."""
    x0, x1 = (1, -1) if flip else (-1, 1)
    return {
        "upper_left": [x0, 1, z],
        "lower_left": [x0, -1, z],
        "upper_right": [x1, 1, z],
        "image": image,
    }


def test_upper_left_texel_is_at_the_upper_left_corner_and_mirrored_from_behind(tmp_path):
    red, green, blue, white = [255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255] * 4
    name = write_texture(tmp_path, "quad.png", [[red, green], [blue, white]])
    cam = {
        "eye": [0, 0, 2],
        "lookat": [0, 0, 0],
        "up": [0, 1, 0],
        "fov_angle": 53.13,
        "width": 8,
        "height": 8,
    }  # the 2 x 2 board nearly fills the view
    front = rendered(scene_dict(camera=cam, spheres=[], billboards=[_facing_board(name)]), tmp_path)
    pixels = quantize(front.rgb)
    assert pixels[0, 0].tolist() == [255, 0, 0] and pixels[0, -1].tolist() == [0, 255, 0]
    assert pixels[-1, 0].tolist() == [0, 0, 255] and pixels[-1, -1].tolist() == [255, 255, 255]
    behind_cam = dict(cam, eye=[0, 0, -2])
    back = rendered(
        scene_dict(camera=behind_cam, spheres=[], billboards=[_facing_board(name)]), tmp_path
    )
    pixels = quantize(back.rgb)
    assert pixels[0, -1].tolist() == [255, 0, 0] and pixels[0, 0].tolist() == [0, 255, 0]


def test_transparent_texels_let_the_ray_go_on_to_what_is_behind(tmp_path):
    hole, wall = [0, 0, 0, 0], [200, 200, 200, 255]
    name = write_texture(tmp_path, "holes.png", [[hole, wall], [wall, hole]])
    scene = scene_dict(billboards=[_facing_board(name, z=3.0)])  # it fills the view
    scene["camera"].update(width=24, height=24)
    scene["spheres"][0]["radius"] = 2.5
    index = rendered(scene, tmp_path).object_index
    assert index[0, 0] == 0 and index[-1, -1] == 0  # through the holes to the sphere
    assert index[0, -1] == 1 and index[-1, 0] == 1  # the opaque texels are the billboard


def test_texels_with_alpha_below_128_are_holes_and_from_128_opaque(tmp_path):
    name = write_texture(tmp_path, "edge.png", [[[200, 0, 0, 127], [200, 0, 0, 128]]])
    scene = scene_dict(billboards=[_facing_board(name, z=3.0)])
    scene["camera"].update(width=24, height=24)
    scene["spheres"][0]["radius"] = 2.5
    index = rendered(scene, tmp_path).object_index
    assert (index[:, :12] == 0).all()  # alpha 127: through the hole to the sphere
    assert (index[:, 12:] == 1).all()  # alpha 128: the billboard


def test_supersampling_averages_before_quantising():
    # a 1 x 1 orthographic image whose left half is a white billboard: 4 samples give 0.5
    cam = {
        "eye": [0, 0, 5],
        "lookat": [0, 0, 0],
        "up": [0, 1, 0],
        "fov_angle": 90,
        "width": 1,
        "height": 1,
        "projection": "orthographic",
    }
    board = {
        "upper_left": [-20, 20, 0],
        "lower_left": [-20, -20, 0],
        "upper_right": [0, 20, 0],
        "color": [1, 1, 1],
    }
    result = rendered(scene_dict(camera=cam, spheres=[], billboards=[board]), samples=2)
    assert result.rgb[0, 0].tolist() == [0.5, 0.5, 0.5]
    assert quantize(result.rgb)[0, 0].tolist() == [128, 128, 128]


@pytest.mark.parametrize("samples", [2, 3])
def test_object_index_and_t_describe_the_pixel_centre_whatever_the_samples(samples):
    scene = scene_from_dict(scene_dict())
    one, many = render(scene), render(scene, samples=samples)
    assert np.array_equal(one.object_index, many.object_index)
    assert np.array_equal(one.t, many.t)


PICTURES_ALONE = [
    ("classic", 1, False),
    ("classic", 2, False),  # no sample at the centre
    ("classic_lit", 3, True),
    ("soft_shadows", 1, False),  # distributed
]


@pytest.mark.parametrize("name,samples,adaptive", PICTURES_ALONE)
def test_the_picture_alone_is_the_picture_with_hits_and_casts_no_centre_ray(
    name, samples, adaptive
):
    from raykit.engine.regions import Plan
    from raykit.render import cast

    scene = load_scene(SCENES / f"{name}.json")
    scene = replace(scene, camera=replace(scene.camera, width=40, height=30))
    told = []
    whole = render(scene, samples, adaptive=adaptive, engine="numpy")
    alone = render(
        scene, samples, adaptive=adaptive, engine="numpy", hits=False, progress=told.append
    )
    assert alone.object_index is None and alone.t is None
    assert np.array_equal(alone.rgb, whole.rgb)
    assert sum(told) == 40 * 30
    batches = list(Plan(scene, cast, samples, hits=False).batches())
    assert not any(batch.centre or not batch.colour for batch in batches)
    assert sum(batch.finishes for batch in batches) == 40 * 30


def test_band_and_tile_sizes_do_not_change_the_image(monkeypatch):
    import raykit.engine.tiles as tiles

    scene = scene_from_dict(scene_dict())
    whole = render(scene, samples=2, skip_hidden=False)
    monkeypatch.setattr(tiles, "RAYS_PER_BAND", 70)  # two rows of 32 per band
    monkeypatch.setattr(tiles, "TILE", 5)  # tiles that do not divide the image
    for skip in (False, True):
        other = render(scene, samples=2, skip_hidden=skip)
        assert np.array_equal(whole.rgb, other.rgb)
        assert np.array_equal(whole.object_index, other.object_index)


def test_scene_moved_to_1e6_shows_the_same_objects():
    near = render(load_scene(SCENES / "classic.json")).object_index
    far = render(load_scene(SCENES / "far_away.json")).object_index
    assert np.mean(near == far) >= 0.999


def _rotated(scene: dict, rotation: np.ndarray, shift: np.ndarray) -> dict:
    move = lambda p: (rotation @ np.asarray(p, float) + shift).tolist()  # noqa: E731
    turn = lambda p: (rotation @ np.asarray(p, float)).tolist()  # noqa: E731
    out = {**scene, "camera": dict(scene["camera"])}
    out["camera"]["eye"] = move(scene["camera"]["eye"])
    out["camera"]["lookat"] = move(scene["camera"]["lookat"])
    out["camera"]["up"] = turn(scene["camera"]["up"])
    out["spheres"] = [dict(s, center=move(s["center"])) for s in scene.get("spheres", [])]
    out["billboards"] = [
        dict(b, **{k: move(b[k]) for k in ("upper_left", "lower_left", "upper_right")})
        for b in scene.get("billboards", [])
    ]
    return out


def test_rotating_and_moving_scene_and_camera_together_leaves_the_object_image_unchanged():
    import json

    scene = json.loads((SCENES / "classic.json").read_text())
    scene["camera"].update(width=160, height=120)
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    rotation = q * np.sign(np.linalg.det(q))  # a proper rotation
    before = rendered(scene, SCENES).object_index
    after = rendered(_rotated(scene, rotation, np.array([3e5, -2e5, 7e5])), SCENES).object_index
    assert np.mean(before == after) >= 0.999


def test_object_image_agrees_with_an_independent_tracer_on_random_scenes(tmp_path):
    rng = np.random.default_rng(2024)
    texels = rng.integers(0, 256, size=(5, 7, 4))  # random colours and random holes
    write_texture(tmp_path, "noise.png", texels)
    agree = total = 0
    for _ in range(40):
        scene = random_scene(rng, "noise.png")
        ours = rendered(scene, tmp_path).object_index
        theirs = np.array(trace_object_index(scene, tmp_path))
        agree += int((ours == theirs).sum())
        total += ours.size
        assert np.mean(ours == theirs) >= 0.99
    assert agree / total >= 0.999


def test_texture_of_a_billboard_no_ray_reaches_is_never_decoded(tmp_path):
    name = write_texture(tmp_path, "unseen.png", [[[1, 2, 3, 255]]])
    scene = scene_from_dict(scene_dict(billboards=[_facing_board(name, z=9.0)]), folder=tmp_path)
    render(scene)  # the board is behind the eye
    assert not scene.billboards[0].texture.decoded


def test_scene_without_light_copies_the_colour_of_the_object_at_each_pixel():
    # the slide's first loop: "copy the color of the object at this point to this pixel"
    from dataclasses import replace

    from raykit.render import cast_pixels

    lit = load_scene(SCENES / "classic_lit.json")
    small = replace(lit.camera, width=64, height=48)
    flat = replace(lit, camera=small, lights=(), ambient=None)
    rows, cols = np.indices((48, 64)).reshape(2, -1)
    _, _, hits = cast_pixels(flat, rows, cols)
    assert np.array_equal(render(flat).rgb.reshape(-1, 3), hits.color)
    # with ambient light only, the same colours scaled by it: darker than the objects' own
    ambient = render(replace(flat, ambient=lit.ambient)).rgb.reshape(-1, 3)
    seen = hits.index >= 0
    assert np.allclose(ambient[seen], hits.color[seen] * lit.ambient)

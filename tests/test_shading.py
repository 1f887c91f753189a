"""Stage 4: lights, shading, shadows and mirrors (FOCG 4.5-4.9), and what is skipped."""

import json

import numpy as np
import pytest

import raykit.render
import raykit.shading
import raykit.surfaces
from conftest import SCENES, random_scene, scene_dict, shifted_scene, write_texture
from independent_tracer import trace_shaded
from raykit.io.images import quantize
from raykit.io.scene_json import scene_from_dict
from raykit.lights import DirectionalLight, PointLight, toward_light
from raykit.mirrors import reflect
from raykit.render import render
from raykit.shading import blinn_phong, lambert
from raykit.spheres import sphere_normals

V1_SCENES = ["classic", "cutouts", "orthographic", "wide_fov", "far_away"]
LIT_SCENES = ["classic_lit", "mirror_balls", "shadow_on_billboard"]


def lit(**overrides) -> dict:
    """The minimal scene with a light over the camera's shoulder and a floor under the ball."""
    floor = {"upper_left": [-5, -1, -5], "lower_left": [-5, -1, 5], "upper_right": [5, -1, -5]}
    scene = scene_dict(
        lights=[{"type": "point", "position": [2, 4, 5], "color": [1, 1, 1]}],
        ambient=[0.1, 0.1, 0.1],
        billboards=[{**floor, "color": [0.5, 0.5, 0.5]}],
    )
    scene.update(overrides)
    return scene


# -- the formulas -----------------------------------------------------------------------------


def test_lambert_is_kd_times_intensity_times_cosine_and_zero_from_behind():
    n = np.array([[0.0, 1, 0]] * 3)
    l = np.array([[0.0, 1, 0], [np.sqrt(0.5), np.sqrt(0.5), 0], [0, -1, 0]])
    kd = np.array([[0.5, 1.0, 0.2]] * 3)
    got = lambert(kd, np.array([1.0, 0.5, 2.0]), n, l)
    np.testing.assert_allclose(got[0], [0.5, 0.5, 0.4])
    np.testing.assert_allclose(got[1], np.array([0.5, 0.5, 0.4]) * np.sqrt(0.5))
    np.testing.assert_array_equal(got[2], [0, 0, 0])


def test_blinn_phong_peaks_when_the_half_vector_is_the_normal():
    n = np.array([[0.0, 0, 1]] * 2)
    l = np.array([[0.6, 0, 0.8], [1.0, 0, 0.0]])
    v = np.array([[-0.6, 0, 0.8], [-0.6, 0, 0.8]])  # mirror image of the first l: h = n
    ks = np.ones((2, 3))
    got = blinn_phong(ks, np.ones(3), n, l, v, 50.0)
    np.testing.assert_allclose(got[0], 1.0)
    h = (l[1] + v[1]) / np.linalg.norm(l[1] + v[1])
    np.testing.assert_allclose(got[1], h[2] ** 50)
    assert got[1, 0] < 0.5  # a small highlight


def test_reflect_turns_round_the_normal_component_only():
    rng = np.random.default_rng(8)
    d = rng.normal(size=(50, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    n = rng.normal(size=(50, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    r = reflect(d, n)
    np.testing.assert_allclose(np.sum(r * n, 1), -np.sum(d * n, 1), atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(r, axis=1), 1.0)
    np.testing.assert_allclose(
        r - np.sum(r * n, 1)[:, None] * n, d - np.sum(d * n, 1)[:, None] * n, atol=1e-12
    )
    np.testing.assert_allclose(reflect(d, -n), r, atol=1e-12)  # either way round


def test_toward_light_points_from_the_surface_to_the_light():
    points = np.array([[0.0, 0, 0], [1, 2, 3]])
    l, distance = toward_light(DirectionalLight(np.array([0, -2.0, 0]), np.ones(3)), points)
    np.testing.assert_allclose(l, [[0, 1, 0], [0, 1, 0]])
    assert np.all(np.isinf(distance))
    l, distance = toward_light(PointLight(np.array([0.0, 4, 0]), np.ones(3)), points)
    np.testing.assert_allclose(l[0], [0, 1, 0])
    np.testing.assert_allclose(distance, [4, np.sqrt(1 + 4 + 9)])
    np.testing.assert_allclose(l[1], np.array([-1, 2, -3]) / np.sqrt(14))


def test_sphere_normal_is_unit_and_outward():
    center, radius = np.array([1.0, 2, 3]), 2.5
    rng = np.random.default_rng(1)
    directions = rng.normal(size=(20, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    np.testing.assert_allclose(
        sphere_normals(center + radius * directions, center, radius), directions
    )


# -- v1 scenes are untouched -------------------------------------------------------------------


@pytest.mark.parametrize("name", V1_SCENES)
def test_v1_scene_runs_no_shading_code(monkeypatch, name):
    def refuse(*args, **kwargs):
        raise AssertionError("shading ran for a v1 scene")

    monkeypatch.setattr(raykit.render, "shade", refuse)
    monkeypatch.setattr(raykit.render, "secondary_caster", refuse)
    data = json.loads((SCENES / f"{name}.json").read_text())
    data["camera"].update(width=64, height=48)
    scene = scene_from_dict(data, folder=SCENES)
    assert not scene.lit and not scene.materials.any_mirror
    for samples, adaptive in ((1, False), (3, True)):
        assert (render(scene, samples, adaptive=adaptive).object_index >= 0).any()


def test_flat_colours_are_the_objects_own_without_lights():
    out = render(scene_from_dict(scene_dict()))
    assert np.array_equal(
        out.rgb[out.object_index == 0], np.tile([1.0, 0, 0], ((out.object_index == 0).sum(), 1))
    )


def test_an_unlit_mirror_adds_km_times_what_it_reflects():
    scene = scene_dict(
        spheres=[
            {"center": [0, 0, 0], "radius": 1, "color": [0.2, 0.2, 0.2], "mirror": [0.5, 0.5, 0.5]}
        ],
        background=[0.0, 0.0, 1.0],
    )
    out = render(scene_from_dict(scene))
    centre = out.rgb[12, 16]  # reflects straight back to the background
    np.testing.assert_allclose(centre, [0.2, 0.2, 0.2 + 0.5])


# -- agreement with an independent renderer ------------------------------------------------------


@pytest.mark.parametrize("name", LIT_SCENES)
def test_lit_example_scene_agrees_with_an_independent_renderer(name):
    data = json.loads((SCENES / f"{name}.json").read_text())
    data["camera"].update(width=48, height=36)
    ours = render(scene_from_dict(data, folder=SCENES))
    index, rgb = trace_shaded(data, SCENES)
    assert np.array_equal(ours.object_index, np.array(index))
    np.testing.assert_allclose(ours.rgb, np.array(rgb, float), atol=1e-9)


def _random_lit_scene(rng, texture):
    scene = random_scene(rng, texture)
    scene["ambient"] = rng.uniform(0, 0.3, 3).tolist()
    scene["lights"] = [
        {
            "type": "directional",
            "direction": rng.normal(size=3).tolist(),
            "color": rng.uniform(0, 1, 3).tolist(),
        }
        if rng.random() < 0.5
        else {
            "type": "point",
            "position": rng.uniform(-6, 6, 3).tolist(),
            "color": rng.uniform(0, 1.5, 3).tolist(),
        }
        for _ in range(int(rng.integers(1, 3)))
    ]
    eye = np.array(scene["camera"]["eye"])
    for sphere in scene["spheres"]:
        sphere.update(specular=rng.uniform(0, 1, 3).tolist(), shininess=float(rng.uniform(1, 100)))
        inside = np.linalg.norm(eye - sphere["center"]) < sphere["radius"]
        if rng.random() < 0.4 and not inside:  # the independent tracer skips a mirror's own
            sphere["mirror"] = rng.uniform(0, 1, 3).tolist()  # surface, so not from inside
    for board in scene["billboards"]:
        if rng.random() < 0.3:
            board["mirror"] = rng.uniform(0, 1, 3).tolist()
    scene["max_depth"] = int(rng.integers(0, 5))
    scene["shadows"] = bool(rng.random() < 0.8)
    return scene


def test_random_lit_scenes_agree_with_an_independent_renderer(tmp_path):
    rng = np.random.default_rng(48)
    write_texture(tmp_path, "noise.png", rng.integers(0, 256, (5, 7, 4)))
    same_object = close = total = 0
    for _ in range(30):
        scene = _random_lit_scene(rng, "noise.png")
        ours = render(scene_from_dict(scene, folder=tmp_path))
        index, rgb = trace_shaded(scene, tmp_path)
        agree = ours.object_index == np.array(index)
        near = np.abs(ours.rgb - np.array(rgb, float)).max(axis=-1) <= 1e-6
        same_object += int(agree.sum())
        close += int((agree & near).sum())
        total += agree.size
    assert same_object / total >= 0.999
    assert close / total >= 0.995  # a shadow or mirror edge may pass between the two methods


# -- robust secondary rays --------------------------------------------------------------------


def _no_shadow_scene() -> dict:
    """A ball and a floor lit from the camera's side: no point that faces the light is in
    shadow, so each of them must be lit fully; grazing light on the floor's far part."""
    return lit(
        spheres=[{"center": [0, 0, 0], "radius": 1, "color": [0.9, 0.9, 0.9]}],
        lights=[{"type": "directional", "direction": [0, -0.05, -1], "color": [1, 1, 1]}],
        billboards=[
            {
                "upper_left": [-50, -1.5, -50],
                "lower_left": [-50, -1.5, 50],
                "upper_right": [50, -1.5, -50],
                "color": [0.5, 0.5, 0.5],
            }
        ],
        camera={
            "eye": [0, 0.5, 6],
            "lookat": [0, -0.3, 0],
            "up": [0, 1, 0],
            "fov_angle": 60,
            "width": 96,
            "height": 72,
        },
    )


def _acne(scene: dict, dtype) -> int:
    """Pixels darker than the unshadowed shading: ambient + Lambert with no blocker."""
    s = scene_from_dict(scene)
    out = render(s, dtype=dtype)
    light = s.lights[0]
    l = -light.direction / np.linalg.norm(light.direction)
    expected = np.empty_like(out.rgb)
    for i, obj in enumerate(s.objects):
        on = out.object_index == i
        if i == 0:
            rows, cols = np.nonzero(on)
            # the normal from the renderer's own hit point
            from raykit.render import cast_pixels

            o, d, hits = cast_pixels(s, rows, cols)
            n = sphere_normals(o + hits.t[:, None] * d, obj.center, obj.radius)
        else:
            n = np.tile([0.0, 1, 0], (on.sum(), 1))
        expected[on] = obj.color * (s.ambient + np.maximum(0, n @ l)[:, None] * light.color)
    darker = (out.rgb - expected).max(axis=-1) < -1e-4
    return int((darker & (out.object_index >= 0)).sum())


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("offset", [0.0, 1e6, 1e7])
def test_no_shadow_acne_at_large_coordinates(dtype, offset):
    assert _acne(shifted_scene(_no_shadow_scene(), [offset, -offset, offset]), dtype) == 0


def test_without_the_offset_there_is_acne(monkeypatch):
    """The acne test can fail: with secondary rays started on the surface it does."""
    monkeypatch.setattr(raykit.surfaces, "OFFSET_FACTOR", 0)
    assert _acne(shifted_scene(_no_shadow_scene(), [1e6, 1e6, 1e6]), np.float64) > 50


def test_no_light_leaks_under_a_wall_standing_on_the_floor():
    """A wall stands on the floor; the light is behind it. Every floor point behind the wall,
    however close to its foot, is in shadow: the offset never lifts a shadow ray past it."""
    floor = {
        "upper_left": [-4, 0, -4],
        "lower_left": [-4, 0, 4],
        "upper_right": [4, 0, -4],
        "color": [1, 1, 1],
    }
    wall = {
        "upper_left": [-4, 3, 0],
        "lower_left": [-4, 0, 0],
        "upper_right": [4, 3, 0],
        "color": [1, 1, 1],
    }
    scene = lit(
        spheres=[],
        billboards=[floor, wall],
        ambient=[0, 0, 0],
        lights=[{"type": "point", "position": [0, 2.5, -1.0], "color": [1, 1, 1]}],
        camera={
            "eye": [0, 6, 3],
            "lookat": [0, 0, 0.05],
            "up": [0, 0, -1],
            "fov_angle": 3,
            "width": 64,
            "height": 64,
        },
    )
    for offset in (0.0, 1e6):
        out = render(scene_from_dict(shifted_scene(scene, [offset, offset, offset])))
        floor_seen = out.object_index == 0
        assert floor_seen.sum() > 1000
        assert np.all(out.rgb[floor_seen] == 0), "light leaked under the wall"


# -- what is skipped ---------------------------------------------------------------------------


class Counting:
    """Wraps a function and counts its calls and the rows of its ``rows_in``-th argument."""

    def __init__(self, function, rows_in: int = 0):
        self.function, self.rows_in, self.calls, self.rows = function, rows_in, 0, 0

    def __call__(self, *args):
        self.calls += 1
        self.rows += len(args[self.rows_in])
        return self.function(*args)


def test_no_shadow_rays_when_shadows_are_off_or_one_object_is_alone(monkeypatch):
    counted = Counting(raykit.shading.in_shadow, rows_in=2)
    monkeypatch.setattr(raykit.shading, "in_shadow", counted)
    render(scene_from_dict(lit(shadows=False)))
    render(scene_from_dict(lit(billboards=[])))  # a lone sphere cannot shadow itself
    assert counted.calls == 0
    render(scene_from_dict(lit()))
    assert counted.calls > 0


def test_shadow_rays_only_from_points_facing_the_light(monkeypatch):
    counted = Counting(raykit.shading.in_shadow, rows_in=2)
    monkeypatch.setattr(raykit.shading, "in_shadow", counted)
    scene = lit(lights=[{"type": "directional", "direction": [0, 0, 1]}])  # lights the back only
    out = render(scene_from_dict(scene))
    assert counted.calls == 0
    np.testing.assert_allclose(out.rgb[12, 16], [0.1, 0, 0])  # ambient only


def test_no_reflection_rays_without_mirrors_and_only_mirror_pixels_spawn_them(monkeypatch):
    counted = Counting(raykit.shading.reflect)
    monkeypatch.setattr(raykit.shading, "reflect", counted)
    render(scene_from_dict(lit()))
    assert counted.calls == 0
    scene = lit()
    scene["spheres"][0]["mirror"] = [0.5, 0.5, 0.5]
    scene["max_depth"] = 1
    out = render(scene_from_dict(scene))
    assert counted.rows == (out.object_index == 0).sum() > 0  # one mirror ray per sphere pixel


def test_max_depth_bounds_the_bounces_between_two_facing_mirrors():
    mirror = {"color": [0, 0, 0], "mirror": [0.5, 0.5, 0.5]}
    scene = scene_dict(
        camera={
            "eye": [0, 0, 0],
            "lookat": [0, 0, -1],
            "up": [0, 1, 0],
            "fov_angle": 10,
            "width": 3,
            "height": 3,
        },
        background=[1, 1, 1],
        spheres=[],
        billboards=[
            {
                "upper_left": [-5, 5, -2],
                "lower_left": [-5, -5, -2],
                "upper_right": [5, 5, -2],
                **mirror,
            },
            {
                "upper_left": [-5, 5, 2],
                "lower_left": [-5, -5, 2],
                "upper_right": [5, 5, 2],
                **mirror,
            },
        ],
    )
    for depth in range(5):
        out = render(scene_from_dict({**scene, "max_depth": depth}))
        np.testing.assert_allclose(out.rgb[1, 1], 0.0, atol=0)  # never escapes: black mirrors
    scene["billboards"][1]["color"] = [0.2, 0.4, 0.8]  # the mirror behind the eye has a colour
    scene["billboards"][1]["mirror"] = [0, 0, 0]
    for depth in range(4):
        out = render(scene_from_dict({**scene, "max_depth": depth}))
        expected = [0, 0, 0] if depth == 0 else 0.5 * np.array([0.2, 0.4, 0.8])
        np.testing.assert_allclose(out.rgb[1, 1], expected)


def test_float32_changes_no_object_and_little_colour_on_the_lit_scenes():
    for name in LIT_SCENES:
        data = json.loads((SCENES / f"{name}.json").read_text())
        data["camera"].update(width=160, height=120)
        scene = scene_from_dict(data, folder=SCENES)
        wide, single = render(scene), render(scene, dtype=np.float32)
        assert np.array_equal(wide.object_index, single.object_index), name
        changed = np.any(quantize(wide.rgb) != quantize(single.rgb), axis=-1)
        assert changed.mean() <= 0.002, (name, changed.sum())


# -- rules the format docs settle (docs/scene-format.md, "Settled details") -------------------


def test_an_empty_lights_list_is_unlit_and_black_ambient_is_lit():
    plain = render(scene_from_dict(scene_dict(background=[0, 0, 0.5]))).rgb
    no_lights = scene_from_dict(scene_dict(background=[0, 0, 0.5], lights=[]))
    assert not no_lights.lit
    assert np.array_equal(render(no_lights).rgb, plain)  # flat colours, as with no field
    black = scene_from_dict(scene_dict(background=[0, 0, 0.5], ambient=[0, 0, 0]))
    assert black.lit  # ambient counts as lit, even black: L = ka·0 = 0 on every object
    image = render(black)
    hit = image.object_index >= 0
    assert hit.any() and (image.rgb[hit] == 0).all()
    assert (image.rgb[~hit] == [0, 0, 0.5]).all()  # the background is never shaded


def _inside_a_sphere(light: dict, **sphere) -> np.ndarray:
    """The camera at a big sphere's centre, looking along -z; its one light ``light``."""
    scene = scene_dict(
        camera={"eye": [0, 0, 0], "lookat": [0, 0, -1], "up": [0, 1, 0], "fov_angle": 90}
        | {"width": 5, "height": 5},
        spheres=[{"center": [0, 0, 0], "radius": 3, "color": [0.5, 0.5, 0.5], **sphere}],
        lights=[light],
    )
    return render(scene_from_dict(scene)).rgb


def test_inside_a_sphere_the_normal_still_points_out():
    # a light outside lights the inside wherever the outward normal faces it: n·l > 0 with
    # n = (p - c)/r, as if the wall let the light through
    outside = _inside_a_sphere({"type": "directional", "direction": [0, 0, 1]})
    assert outside[2, 2].tolist() == [0.5, 0.5, 0.5]  # n = (0, 0, -1) = l: kd·I·1
    assert (outside[:, :, 0] > 0).all()  # every pixel sees the lit far wall
    # a light inside lights none of it: n·l < 0 at every point of the wall
    inside = _inside_a_sphere({"type": "point", "position": [0.5, 0.2, 0.1]})
    assert (inside == 0).all()


def test_no_highlight_where_the_half_vector_is_undefined():
    # seen from inside, the centre pixel's ray runs straight toward the light: l = -v, l + v = 0
    image = _inside_a_sphere(
        {"type": "directional", "direction": [0, 0, 1]}, specular=[1, 1, 1], shininess=8
    )
    assert np.isfinite(image).all()
    assert image[2, 2].tolist() == [0.5, 0.5, 0.5]  # diffuse only, no NaN


def test_a_lamp_on_a_wall_is_not_shadowed_by_that_wall():
    # the shadow ray's reach is measured from its offset start and shortened by the offset at
    # the light's end, so the surface the lamp sits on never blocks it (it used to speckle)
    floor = {"upper_left": [-4, -1, -6], "lower_left": [-4, -1, 4], "upper_right": [4, -1, -6]}
    wall = {"upper_left": [-4, 3, -2], "lower_left": [-4, -1, -2], "upper_right": [4, 3, -2]}
    camera = {"eye": [0, 1, 6], "lookat": [0, 0, -2], "up": [0, 1, 0], "fov_angle": 60}
    for position in ([0.3, 1.7, -2], [0.1, 0.2, -2], [1 / 3, 2 / 3, -2]):
        scene = scene_dict(
            camera=camera | {"width": 160, "height": 120},
            spheres=[],
            billboards=[{**floor, "color": [0.6, 0.6, 0.6]}, {**wall, "color": [0.3, 0.3, 0.8]}],
            lights=[{"type": "point", "position": position}],
        )
        shadowed = render(scene_from_dict(scene)).rgb
        unshadowed = render(scene_from_dict(scene | {"shadows": False})).rgb
        assert np.array_equal(shadowed, unshadowed), position
        # a ball just in front of the lamp still casts a shadow on the floor
        ball = {"center": [position[0], position[1], -1.9], "radius": 0.05, "color": [1, 1, 1]}
        blocked = render(scene_from_dict(scene | {"spheres": [ball]})).rgb
        assert (blocked.sum(axis=-1) < unshadowed.sum(axis=-1) - 1e-9).any(), position

"""Area lights and soft shadows (FOCG 13.4.2), format v2 and its errors, and the distributed
render: the same seed gives the same bytes whatever the tiling, the compiled engine refuses
what it cannot render yet. Seeded throughout."""

import json

import numpy as np
import pytest
from schemas import schema_validator

from conftest import SCENES, scene_dict
from raykit.billboards import Billboard
from raykit.camera import Camera
from raykit.cli import main
from raykit.engine.choice import choose, compiled_available
from raykit.engine.noise import PixelSamples
from raykit.io.errors import SceneError
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.lights import AreaLight, PointLight, area_intensity, sampled, toward_light
from raykit.render import cast, cast_pixels, render, secondary_caster
from raykit.sampling import Sampling
from raykit.scene import Scene
from raykit.shading import shade

SCHEMA_V2 = schema_validator("scene-v2.schema.json")
PANEL = {"type": "area", "corner": [-1, 4, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2]}
SPHERE = {"center": [0, 0, 0], "radius": 1, "color": [1, 0, 0]}
BOARD = {"upper_left": [-1, 1, -2], "lower_left": [-1, -1, -2], "upper_right": [1, 1, -2],
         "color": [0, 1, 0]}  # fmt: skip


def _penumbra_scene(shadows: bool = True) -> Scene:
    """A white floor (y = 0), a 2 x 2 area light at y = 4 over x, z in [-1, 1], and a blocker
    at y = 2 over x < 0: below x = -3 the light is hidden, below x = 3 seen whole, and below
    x = 0 the blocker's edge cuts it in half."""
    floor = Billboard(
        np.array([-20.0, 0, -20]), np.array([-20.0, 0, 20]), np.array([20.0, 0, -20]),
        np.ones(3),
    )  # fmt: skip
    blocker = Billboard(
        np.array([-20.0, 2, -20]), np.array([-20.0, 2, 20]), np.array([0.0, 2, -20]),
        np.ones(3),
    )  # fmt: skip
    light = AreaLight(np.array([-1.0, 4, -1]), np.array([2.0, 0, 0]), np.array([0.0, 0, 2]),
                      np.ones(3))  # fmt: skip
    camera = Camera(np.array([0.0, 10, 10]), np.zeros(3), np.array([0.0, 1, 0]), 40, 8, 8)
    return Scene(camera, (), (floor, blocker), lights=(light,), shadows=shadows)


def _lit_fraction(x: float, samples: int = 256) -> float:
    """The share of the light a floor point at (x, 0, 0) receives: its shading with shadows
    over its shading without, each the sum over ``samples`` jittered points of the light."""
    sums = []
    for shadows in (True, False):
        scene = _penumbra_scene(shadows)
        origins = np.tile([[x, 1.0, 0.0]], (samples, 1))  # from just above, straight down,
        directions = np.tile([[0.0, -1.0, 0.0]], (samples, 1))  # below the blocker's height
        hits = cast(scene, origins, directions)
        numbers = PixelSamples(Sampling(samples, "jittered", 44), 4)
        on_light = np.stack([numbers.of(np.array([0]), k)[0, 2:4] for k in range(samples)])
        colors = shade(
            scene, secondary_caster(scene), origins, directions, hits, on_light[:, None, None, :]
        )
        sums.append(colors[:, 0].sum())
    return sums[0] / sums[1]


def test_soft_shadow_fully_lit_fully_shadowed_and_half_in_the_penumbra():
    assert _lit_fraction(3.0) == 1.0
    assert _lit_fraction(-3.0) == 0.0
    assert abs(_lit_fraction(0.0) - 0.5) < 0.02


def _corner_form_factor(a: float, b: float, h: float) -> float:
    """The form factor from a small patch to the parallel a x b rectangle h above it, the patch
    under one of its corners (the closed form of radiometry's tables): the share of the light a
    diffuse patch receives that an emitter covering its whole sky would send."""
    x, y = a / h, b / h
    sx, sy = np.sqrt(1 + x * x), np.sqrt(1 + y * y)
    return (x / sx * np.arctan(y / sx) + y / sy * np.arctan(x / sy)) / (2 * np.pi)


@pytest.mark.parametrize(("a", "b", "h"), [(2.0, 3.0, 1.5), (0.5, 0.5, 4.0), (6.0, 1.0, 0.5)])
def test_a_physically_based_area_light_gives_a_diffuse_point_its_form_factor(a, b, h):
    """Under a physically based light of radiance L, a diffuse point of reflectance kd reflects
    kd·L·F (F the form factor to the light, radiometry's closed form): the mean of the shading
    over the light's points converges to it."""
    samples = 4096
    floor = Billboard(np.array([-20.0, 0, -20]), np.array([-20.0, 0, 20]),
                      np.array([20.0, 0, -20]), np.full(3, 0.5))  # fmt: skip
    corner, edge1, edge2 = np.array([0.0, h, 0]), np.array([a, 0, 0]), np.array([0.0, 0, b])
    radiance = np.array([2.0, 1.0, 0.5])
    origins = np.tile([[0.0, 1e-3, 0.0]], (samples, 1))  # the floor point below the corner
    directions = np.tile([[0.0, -1.0, 0.0]], (samples, 1))
    numbers = PixelSamples(Sampling(samples, "jittered", 57), 4)
    on_light = np.stack([numbers.of(np.array([0]), k)[0, 2:4] for k in range(samples)])
    light = AreaLight(corner, edge1, edge2, radiance, physical=True)
    camera = Camera(np.array([0.0, 10, 10]), np.zeros(3), np.array([0.0, 1, 0]), 40, 8, 8)
    scene = Scene(camera, (), (floor,), lights=(light,))
    hits = cast(scene, origins, directions)
    colors = shade(scene, secondary_caster(scene), origins, directions, hits,
                   on_light[:, None, None, :])  # fmt: skip
    expected = 0.5 * radiance * _corner_form_factor(a, b, h)
    np.testing.assert_allclose(colors.mean(axis=0), expected, rtol=2e-3)


def test_a_physically_based_area_light_lights_only_its_front():
    """a × b points down: a point above the light gets nothing, one below it gets light."""
    light = AreaLight(np.array([-1.0, 4, -1]), np.array([2.0, 0, 0]), np.array([0.0, 0, 2]),
                      np.ones(3), physical=True)  # fmt: skip
    assert np.cross(light.edge1, light.edge2)[1] < 0
    points = np.array([[0.0, 6, 0], [0.0, 0, 0]])
    l, distance = toward_light(sampled(light, np.full((2, 2), 0.5)), points)
    below = area_intensity(light, l, distance)
    assert below[0].tolist() == [0, 0, 0] and (below[1] == 4 * 1 / (np.pi * 16)).all()


def test_a_sampled_area_light_is_a_point_light_at_its_points():
    light = AreaLight(np.zeros(3), np.array([2.0, 0, 0]), np.array([0.0, 4, 0]), np.ones(3))
    point = sampled(light, np.array([[0.5, 0.25], [0.0, 1.0]]))
    assert isinstance(point, PointLight)
    assert point.position.tolist() == [[1.0, 1.0, 0.0], [0.0, 4.0, 0.0]]


def test_an_area_light_shrunk_to_a_point_lights_as_the_point_light():
    data = scene_dict(version=2, lights=[{**PANEL, "edge1": [1e-9, 0, 0], "edge2": [0, 0, 1e-9]}])
    data["ambient"] = [0.1, 0.1, 0.1]
    rows, cols = np.divmod(np.arange(32 * 24), 32)
    colors = []
    for light in (data["lights"][0], {"type": "point", "position": [-1, 4, -1]}):
        scene = scene_from_dict({**data, "lights": [light]})
        origins, directions, hits = cast_pixels(scene, rows, cols)
        uniforms = np.random.default_rng(1).random((len(rows), scene.max_depth + 1, 1, 2))
        colors.append(shade(scene, secondary_caster(scene), origins, directions, hits, uniforms))
    assert np.abs(colors[0] - colors[1]).max() < 1e-6 and colors[1].max() > 0.5


def _small(name: str, **render_settings) -> Scene:
    data = json.loads((SCENES / name).read_text())
    data["camera"].update(width=40, height=30)
    data["render"].update(render_settings)
    return scene_from_dict(data, source=name, folder=SCENES)


@pytest.mark.parametrize("sampler", ["random", "jittered", "sobol"])
def test_the_same_seed_gives_the_same_bytes_whatever_the_tiles(sampler):
    scene = _small("soft_shadows.json", samples_per_pixel=4, sampler=sampler)
    tiled = render(scene, engine="numpy").rgb
    banded = render(scene, engine="numpy", skip_hidden=False).rgb
    assert tiled.tobytes() == banded.tobytes()
    assert tiled.tobytes() == render(scene, engine="numpy").rgb.tobytes()
    other = _small("soft_shadows.json", samples_per_pixel=4, sampler=sampler, seed=2)
    assert tiled.tobytes() != render(other, engine="numpy").rgb.tobytes()


def test_the_distributed_render_keeps_the_centre_rays_hits():
    scene = _small("soft_shadows.json", samples_per_pixel=4)
    from dataclasses import replace

    pinhole = replace(scene, lights=(), sampling=Sampling())
    done, plain = render(scene, engine="numpy"), render(pinhole, engine="numpy")
    assert np.array_equal(done.object_index, plain.object_index)
    assert done.t.tobytes() == plain.t.tobytes()


def test_a_distributed_scene_takes_no_n_by_n_grid_besides():
    with pytest.raises(ValueError, match="samples_per_pixel"):
        render(_small("soft_shadows.json"), samples=2, engine="numpy")


def test_the_compiled_engine_takes_a_distributed_scene_and_auto_keeps_a_small_one_on_numpy():
    # the engines' bytes compared: tests/compiled/test_render.py
    scene = _small("soft_shadows.json")
    assert choose("auto", scene) == "numpy"  # numba's load would cost more than it saves
    if not compiled_available():
        pytest.skip("numba is not installed")
    assert choose("compiled", scene) == "compiled"


def test_the_cli_renders_a_moving_scene_with_either_engine_to_the_same_png_bytes(tmp_path):
    if not compiled_available():
        pytest.skip("numba is not installed")
    data = json.loads((SCENES / "motion_blur.json").read_text())
    data["camera"].update(width=40, height=28)
    for board in data["billboards"]:  # the texture where the scene's folder has it
        board["image"] = str(SCENES / board["image"])
    path = tmp_path / "motion_blur.json"
    path.write_text(json.dumps(data))
    written = {}
    for engine in ("numpy", "compiled"):
        out = tmp_path / f"{engine}.png"
        assert main(["render", str(path), "-o", str(out), "--engine", engine]) == 0
        written[engine] = out.read_bytes()
    assert written["numpy"] == written["compiled"]


# format v2: its fields, its errors, its schema

V2_CASES = [
    # (id, scene overrides, field, words, the v2 schema rejects it too)
    ("area light in a v1 scene", {"lights": [PANEL]}, "lights[0].type", '"version": 2', False),
    ("lens in a v1 scene", {"camera.aperture": 0.1}, "camera.aperture", "format v2", False),
    ("render in a v1 scene", {"render": {"seed": 1}}, "render", "format v2", False),
    ("version 3", {"version": 3}, "version", "must be 2", True),
    (
        "parallel edges",
        {"version": 2, "lights": [{**PANEL, "edge2": [4, 0, 0]}]},
        "lights[0].edge1",
        "must not be parallel to edge2",
        False,
    ),
    (
        "zero edge",
        {"version": 2, "lights": [{**PANEL, "edge2": [0, 0, 0]}]},
        "lights[0].edge2",
        "zero vector",
        False,
    ),
    (
        "area light without an edge",
        {"version": 2, "lights": [{"type": "area", "corner": [0, 1, 0], "edge1": [1, 0, 0]}]},
        "lights[0].edge2",
        "required field is missing",
        True,
    ),
    (
        "area light given a position",
        {"version": 2, "lights": [{**PANEL, "position": [0, 1, 0]}]},
        "lights[0].position",
        "unknown field",
        True,
    ),
    (
        "area light given both a colour and a radiance",
        {"version": 2, "lights": [{**PANEL, "color": [1, 1, 1], "radiance": [2, 2, 2]}]},
        "lights[0].radiance",
        "give one of them",
        True,
    ),
    (
        "negative radiance",
        {"version": 2, "lights": [{**PANEL, "radiance": [1, -2, 1]}]},
        "lights[0].radiance[1]",
        "must be >= 0",
        True,
    ),
    (
        "point light given a radiance",
        {"version": 2, "lights": [{"type": "point", "position": [0, 4, 0], "radiance": [1, 1, 1]}]},
        "lights[0].radiance",
        "is an area light's",
        True,
    ),
    (
        "negative aperture",
        {"version": 2, "camera.aperture": -0.5},
        "camera.aperture",
        "must be >= 0",
        True,
    ),
    (
        "focus distance zero",
        {"version": 2, "camera.focus_distance": 0},
        "camera.focus_distance",
        "must be > 0",
        True,
    ),
    (
        "lens on an orthographic camera",
        {"version": 2, "camera.aperture": 0.2, "camera.projection": "orthographic"},
        "camera.aperture",
        "orthographic camera has no lens",
        False,
    ),
    (
        "unknown sampler",
        {"version": 2, "render": {"sampler": "halton"}},
        "render.sampler",
        '"random" or "jittered" or "sobol"',
        True,
    ),
    (
        "jittered count not a square",
        {"version": 2, "render": {"samples_per_pixel": 10}},
        "render.samples_per_pixel",
        "a square",
        False,
    ),
    (
        "sobol count not a power of two",
        {"version": 2, "render": {"samples_per_pixel": 9, "sampler": "sobol"}},
        "render.samples_per_pixel",
        "power of two",
        False,
    ),
    (
        "negative seed",
        {"version": 2, "render": {"seed": -1}},
        "render.seed",
        "must be >= 0",
        True,
    ),
    (
        "misspelt render field",
        {"version": 2, "render": {"samples": 4}},
        "render.samples",
        "unknown field",
        True,
    ),
    (
        "glossy mirror in a v1 scene",
        {"spheres": [{**SPHERE, "mirror": [1, 1, 1], "glossiness": 0.2}]},
        "spheres[0].glossiness",
        '"version": 2',
        False,
    ),
    (
        "negative glossiness",
        {"version": 2, "spheres": [{**SPHERE, "mirror": [1, 1, 1], "glossiness": -0.1}]},
        "spheres[0].glossiness",
        "must be >= 0",
        True,
    ),
    (
        "glossiness without a mirror",
        {"version": 2, "spheres": [{**SPHERE, "glossiness": 0.2}]},
        "spheres[0].glossiness",
        'give the object a "mirror"',
        False,
    ),
    (
        "shutter closing before it opens",
        {"version": 2, "render": {"shutter": [1, 0.5]}},
        "render.shutter",
        "closes before it opens",
        False,
    ),
    (
        "shutter opening before time 0",
        {"version": 2, "render": {"shutter": [-1, 0.5]}},
        "render.shutter[0]",
        "must be >= 0",
        True,
    ),
    (
        "shutter of three times",
        {"version": 2, "render": {"shutter": [0, 0.5, 1]}},
        "render.shutter",
        "must have 2 numbers",
        True,
    ),
    (
        "moving billboard with a shutter",
        {
            "version": 2,
            "render": {"shutter": [0, 1]},
            "billboards": [{**BOARD, "velocity": [1, 0, 0]}],
        },
        "billboards[0].velocity",
        "only spheres move",
        False,
    ),
]


def _v2_scene(overrides: dict) -> dict:
    scene = scene_dict()
    for key, value in overrides.items():
        if key.startswith("camera."):
            scene["camera"][key.split(".")[1]] = value
        else:
            scene[key] = value
    return scene


@pytest.mark.parametrize(("overrides", "field", "words"), [c[1:4] for c in V2_CASES],
                         ids=[c[0] for c in V2_CASES])  # fmt: skip
def test_a_bad_v2_field_gets_one_line_naming_file_and_field(tmp_path, capsys, overrides, field,
                                                            words):  # fmt: skip
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(_v2_scene(overrides)))
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert info.value.field == field and words in info.value.problem
    assert main(["render", str(path), "-o", str(tmp_path / "out.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"raykit: error: {path}: {field}: ")


@pytest.mark.parametrize(("overrides", "schema_rejects"), [(c[1], c[4]) for c in V2_CASES],
                         ids=[c[0] for c in V2_CASES])  # fmt: skip
def test_the_v2_schema_rejects_exactly_the_structural_errors(overrides, schema_rejects):
    scene = _v2_scene(overrides)
    if "version" not in scene:  # a v1 scene's v2 field: the v2 schema accepts the field itself
        scene["version"] = 2
        assert not list(SCHEMA_V2.iter_errors(scene))
        return
    errors = list(SCHEMA_V2.iter_errors(scene))
    assert bool(errors) == schema_rejects


def test_the_v2_schema_accepts_the_v2_example_scenes_and_they_load():
    found = 0
    for path in sorted(SCENES.glob("*.json")):
        data = json.loads(path.read_text())
        if data.get("$schema", "").endswith("scene-v2.schema.json"):
            SCHEMA_V2.validate(data)
            assert load_scene(path).distributed
            found += 1
    assert found >= 2


def test_a_v2_scene_without_the_new_fields_renders_as_its_v1_self():
    v1 = scene_dict(lights=[{"type": "point", "position": [2, 3, 4]}], ambient=[0.1, 0.1, 0.1])
    v2 = {**v1, "version": 2, "render": {"samples_per_pixel": 1, "seed": 9}}
    v2["camera"] = {**v1["camera"], "aperture": 0}
    one, two = (render(scene_from_dict(d), engine="numpy").rgb for d in (v1, v2))
    assert not scene_from_dict(v2).distributed and one.tobytes() == two.tobytes()

"""One test per class of bad input: a one-line SceneError naming file and field, exit status 2
from the CLI with no traceback, and no output file. The same cases pin down where the JSON
Schema agrees with the loader (structural rules) and where only the loader can tell (geometry,
texture files)."""

import json
import struct
import subprocess
import sys
import zlib

import pytest
from schemas import schema_validator

from conftest import REPO, delete_field, scene_dict, set_field
from raykit.cli import main
from raykit.io.errors import SceneError
from raykit.io.scene_json import load_scene

SCHEMA = schema_validator("scene-v1.schema.json")


BOARD = {"upper_left": [-1, 1, 0], "lower_left": [-1, -1, 0], "upper_right": [1, 1, 0]}

# (id, mutation, field named in the message, words in the message, the schema rejects it too)
CASES = [
    ("missing field", delete_field("camera.eye"), "camera.eye", "required field is missing", True),
    (
        "mistyped field",
        set_field("spheres.0.raduis", 1),
        "spheres[0].raduis",
        'did you mean "radius"',
        True,
    ),
    ("unknown top-level field", set_field("sphere", []), "sphere", 'did you mean "spheres"', True),
    (
        "wrong type",
        set_field("camera.fov_angle", "wide"),
        "camera.fov_angle",
        "must be a number",
        True,
    ),
    ("wrong type: not a list", set_field("spheres", {}), "spheres", "must be a list", True),
    (
        "wrong type: bool as number",
        set_field("spheres.0.radius", True),
        "spheres[0].radius",
        "must be a number",
        True,
    ),
    (
        "wrong length",
        set_field("camera.eye", [0, 0]),
        "camera.eye",
        "must have 3 numbers, got 2",
        True,
    ),
    (
        "velocity of the wrong length",
        set_field("spheres.0.velocity", [0.1, 0]),
        "spheres[0].velocity",
        "must have 3 numbers, got 2",
        True,
    ),
    (
        "NaN",
        set_field("spheres.0.center", [0, float("nan"), 0]),
        "spheres[0].center[1]",
        "finite number, got NaN",
        False,
    ),
    (
        "infinity",
        set_field("camera.lookat", [0, 0, float("-inf")]),
        "camera.lookat[2]",
        "finite number, got -Infinity",
        False,
    ),
    (
        "radius zero",
        set_field("spheres.0.radius", 0),
        "spheres[0].radius",
        "must be > 0, got 0",
        True,
    ),
    (
        "radius negative",
        set_field("spheres.0.radius", -1),
        "spheres[0].radius",
        "must be > 0, got -1",
        True,
    ),
    ("fov_angle zero", set_field("camera.fov_angle", 0), "camera.fov_angle", "must be > 0", True),
    (
        "fov_angle 180",
        set_field("camera.fov_angle", 180),
        "camera.fov_angle",
        "must be < 180",
        True,
    ),
    ("width zero", set_field("camera.width", 0), "camera.width", "must be >= 1", True),
    (
        "height fractional",
        set_field("camera.height", 10.5),
        "camera.height",
        "must be a whole number",
        True,
    ),
    ("width absurd", set_field("camera.width", 20000), "camera.width", "must be <= 16384", True),
    (
        "projection unknown",
        set_field("camera.projection", "fisheye"),
        "camera.projection",
        '"perspective" or "orthographic"',
        True,
    ),
    (
        "colour out of range",
        set_field("spheres.0.color", [1.5, 0, 0]),
        "spheres[0].color[0]",
        "must be <= 1",
        True,
    ),
    (
        "eye equals lookat",
        set_field("camera.lookat", [0, 0, 5]),
        "camera.lookat",
        "same point as eye",
        False,
    ),
    (
        "up parallel",
        set_field("camera.up", [0, 0, -2]),
        "camera.up",
        "parallel to the view direction",
        False,
    ),
    ("up zero", set_field("camera.up", [0, 0, 0]), "camera.up", "zero vector", False),
    (
        "corners collinear",
        set_field("billboards", [{**BOARD, "upper_right": [-1, 3, 0], "color": [1, 1, 1]}]),
        "billboards[0]",
        "collinear",
        False,
    ),
    (
        "corners coincident",
        set_field("billboards", [{**BOARD, "upper_right": [-1, 1, 0], "color": [1, 1, 1]}]),
        "billboards[0].upper_right",
        "coincides with upper_left",
        False,
    ),
    (
        "both image and color",
        set_field("billboards", [{**BOARD, "color": [1, 1, 1], "image": "x.png"}]),
        "billboards[0]",
        "exactly one",
        True,
    ),
    (
        "neither image nor color",
        set_field("billboards", [dict(BOARD)]),
        "billboards[0]",
        "got neither",
        True,
    ),
    (
        "texture missing",
        set_field("billboards", [{**BOARD, "image": "nope.png"}]),
        "billboards[0].image",
        "not found",
        False,
    ),
    (
        "texture is a folder",
        set_field("billboards", [{**BOARD, "image": "."}]),
        "billboards[0].image",
        "folder",
        False,
    ),
    (
        "texture not an image",
        set_field("billboards", [{**BOARD, "image": "notes.txt"}]),
        "billboards[0].image",
        "not an image",
        False,
    ),
    (
        "texture absurdly large",
        set_field("billboards", [{**BOARD, "image": "bomb.png"}]),
        "billboards[0].image",
        "too large to be sane",
        False,
    ),
    # stage 4: lights, materials, shadows, mirror bounces
    (
        "light without type",
        set_field("lights", [{"direction": [0, -1, 0]}]),
        "lights[0].type",
        "required field is missing",
        True,
    ),
    (
        "unknown light type",
        set_field("lights", [{"type": "spot", "position": [0, 1, 0]}]),
        "lights[0].type",
        'must be "directional" or "point"',
        True,
    ),
    (
        "directional light given a position",
        set_field("lights", [{"type": "directional", "position": [0, 1, 0]}]),
        "lights[0].position",
        'takes "direction", not "position"',
        True,
    ),
    (
        "point light without position",
        set_field("lights", [{"type": "point"}]),
        "lights[0].position",
        "required field is missing",
        True,
    ),
    (
        "zero light direction",
        set_field("lights", [{"type": "directional", "direction": [0, 0, 0]}]),
        "lights[0].direction",
        "is the zero vector",
        False,
    ),
    (
        "negative light intensity",
        set_field("lights", [{"type": "point", "position": [0, 1, 0], "color": [1, -0.5, 1]}]),
        "lights[0].color[1]",
        "must be >= 0, got -0.5",
        True,
    ),
    ("negative ambient", set_field("ambient", [0.1, 0.1, -1]), "ambient[2]", "must be >= 0", True),
    (
        "specular above 1",
        set_field("spheres.0.specular", [1.5, 0, 0]),
        "spheres[0].specular[0]",
        "must be <= 1",
        True,
    ),
    (
        "shininess zero",
        set_field("spheres.0.shininess", 0),
        "spheres[0].shininess",
        "must be > 0, got 0",
        True,
    ),
    (
        "mirror not a colour",
        set_field("spheres.0.mirror", 0.5),
        "spheres[0].mirror",
        "must be a list of 3 numbers",
        True,
    ),
    (
        "diffuse on a textured billboard",
        set_field("billboards", [{**BOARD, "image": "t.png", "diffuse": [1, 1, 1]}]),
        "billboards[0].diffuse",
        "takes its diffuse colour from the image",
        True,
    ),
    (
        "shadows not a boolean",
        set_field("shadows", "yes"),
        "shadows",
        "must be true or false",
        True,
    ),
    ("max_depth too deep", set_field("max_depth", 17), "max_depth", "must be <= 16, got 17", True),
    (
        "max_depth not whole",
        set_field("max_depth", 2.5),
        "max_depth",
        "must be a whole number",
        True,
    ),
]


def _png_header_only(width: int, height: int) -> bytes:
    """A PNG that claims a size in its header, with no pixel data: enough to test the guard."""

    def chunk(kind: bytes, data: bytes) -> bytes:
        crc = zlib.crc32(kind + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)

    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IEND", b"")


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "notes.txt").write_text("not an image\n")
    (tmp_path / "bomb.png").write_bytes(_png_header_only(100_000, 100_000))
    return tmp_path


def _write(folder, scene) -> str:
    path = folder / "scene.json"
    path.write_text(json.dumps(scene))  # json writes NaN and Infinity as Python's json reads them
    return str(path)


@pytest.mark.parametrize(
    ("mutate", "field", "words"), [c[1:4] for c in CASES], ids=[c[0] for c in CASES]
)
def test_bad_scene_gets_one_line_naming_file_and_field_exit_2_and_no_output(
    folder, capsys, mutate, field, words
):
    scene = scene_dict()
    mutate(scene)
    path = _write(folder, scene)
    with pytest.raises(SceneError) as info:
        load_scene(path)
    assert isinstance(info.value, ValueError)
    assert info.value.field == field
    out = folder / "out.png"
    assert main(["render", path, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.startswith(f"raykit: error: {path}: {field}: ")
    assert words in err
    assert not out.exists()
    assert [p.name for p in folder.iterdir() if p.name.startswith(".out")] == []


@pytest.mark.parametrize(
    ("mutate", "schema_rejects"), [(c[1], c[4]) for c in CASES], ids=[c[0] for c in CASES]
)
def test_json_schema_rejects_exactly_the_structural_errors(mutate, schema_rejects):
    scene = scene_dict()
    mutate(scene)
    errors = list(SCHEMA.iter_errors(scene))
    if schema_rejects:
        assert errors, "the schema accepts what the loader rejects"
    else:
        assert not errors, "a geometric or file rule belongs to the loader alone"


def test_schema_accepts_every_example_scene():
    for path in sorted((REPO / "scenes").glob("*.json")) + [
        REPO / "scenes/linescan3d/passing_car.json"
    ]:
        if json.loads(path.read_text()).get("$schema", "").endswith("scene-v1.schema.json"):
            SCHEMA.validate(json.loads(path.read_text()))


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("{ not json", "not valid JSON"),
        ("[1, 2]", "must be a JSON object, got a list"),
        ("", "not valid JSON"),
    ],
)
def test_file_that_is_no_scene_object_is_refused(tmp_path, capsys, text, words):
    path = tmp_path / "scene.json"
    path.write_text(text)
    assert main(["render", str(path), "-o", str(tmp_path / "out.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and words in err and str(path) in err


def test_missing_scene_file_is_refused(tmp_path, capsys):
    assert main(["render", str(tmp_path / "nope.json"), "-o", str(tmp_path / "o.png")]) == 2
    assert "scene file not found" in capsys.readouterr().err


def test_undecodable_texture_fails_at_render_time_without_output(tmp_path, capsys):
    # a valid header but truncated pixel data: only decoding finds out
    from PIL import Image

    Image.new("RGB", (64, 64), "red").save(tmp_path / "t.png")
    data = (tmp_path / "t.png").read_bytes()
    (tmp_path / "t.png").write_bytes(data[: len(data) // 2])
    scene = scene_dict(billboards=[{**BOARD, "image": "t.png"}])
    path = _write(tmp_path, scene)
    out = tmp_path / "out.png"
    assert main(["render", path, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "billboards[0].image: texture cannot be decoded" in err and err.count("\n") == 1
    assert not out.exists()


def test_cli_in_a_real_process_prints_no_traceback(folder):
    scene = scene_dict()
    scene["spheres"][0]["radius"] = -1
    path = _write(folder, scene)
    out = folder / "out.png"
    run = subprocess.run(
        [sys.executable, "-m", "raykit", "render", path, "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 2
    assert run.stderr == f"raykit: error: {path}: spheres[0].radius: must be > 0, got -1\n"
    assert "Traceback" not in run.stdout + run.stderr
    assert not out.exists()


def test_plain_spheres_load_in_bulk_exactly_as_field_by_field():
    import numpy as np

    from raykit.io.fields import Field
    from raykit.io.scene_json import _plain_spheres, _read_sphere, scene_from_dict

    rng = np.random.default_rng(12)
    spheres = [
        {
            "center": rng.uniform(-1e6, 1e6, 3).tolist(),
            "radius": float(rng.uniform(1e-3, 9)),
            "color": rng.uniform(0, 1, 3).tolist(),
        }
        for _ in range(200)
    ]
    spheres[3]["radius"] = 2  # a JSON integer
    bulk = _plain_spheres(spheres)
    one_by_one = [_read_sphere(f) for f in Field(spheres, "s").items()]
    assert bulk is not None and len(bulk) == len(one_by_one)
    for a, b in zip(bulk, one_by_one, strict=True):
        assert np.array_equal(a.center, b.center) and a.radius == b.radius
        assert np.array_equal(a.color, b.color) and (a.name, a.material) == (b.name, b.material)
    # anything less plain goes field by field, where the error names the field
    for bad, field in (
        ({"radius": True}, "spheres[1].radius"),
        ({"radius": 0}, "spheres[1].radius"),
        ({"color": [0, 0, 1.5]}, "spheres[1].color[2]"),
        ({"center": [0, 0]}, "spheres[1].center"),
        ({"center": [0, 0, float("nan")]}, "spheres[1].center[2]"),
        ({"center": "abc"}, "spheres[1].center"),
        ({"center": [0, 0, "1"]}, "spheres[1].center[2]"),  # numpy would take "1" as 1.0
        ({"color": [0, 0, None]}, "spheres[1].color[2]"),
        ({"center": [0, 0, [1]]}, "spheres[1].center[2]"),
        ({"center": {"x": 0, "y": 0, "z": 0}}, "spheres[1].center"),
        ({"radius": 10**400}, "spheres[1].radius"),
    ):
        broken = [dict(s) for s in spheres[:3]]
        broken[1].update(bad)
        assert _plain_spheres(broken) is None
        with pytest.raises(SceneError) as info:
            scene_from_dict(scene_dict(spheres=broken))
        assert info.value.field == field
    assert _plain_spheres([spheres[0], 5]) is None
    named = [dict(s) for s in spheres[:3]]
    named[0]["name"] = "first"
    assert _plain_spheres(named) is None
    assert scene_from_dict(scene_dict(spheres=named)).spheres[0].name == "first"


def test_velocities_beside_spheres_read_in_bulk_keep_their_object_index_and_their_errors():
    import numpy as np

    from raykit.io.scene_json import scene_from_dict
    from raykit.spheres import SphereTable

    rng = np.random.default_rng(13)
    spheres = [
        {"center": rng.uniform(-5, 5, 3).tolist(), "radius": 0.5, "color": [1, 1, 1]}
        for _ in range(300)
    ]
    board = {"upper_left": [0, 1, 0], "lower_left": [0, 0, 0], "upper_right": [1, 1, 0],
             "color": [0, 1, 0], "velocity": [0.25, 0, 0]}  # fmt: skip
    scene = scene_from_dict(scene_dict(spheres=spheres, billboards=[board]))
    assert isinstance(scene.spheres, SphereTable)  # read in bulk, with no velocity of its own
    assert scene.velocities.shape == (301, 3)
    assert not scene.velocities[:300].any() and scene.velocities[300].tolist() == [0.25, 0, 0]
    # a moving sphere among plain ones: field by field, its velocity at its own index
    moving = [dict(s) for s in spheres]
    moving[123]["velocity"] = [0, 0.5, 0]
    velocities = scene_from_dict(scene_dict(spheres=moving)).velocities
    assert velocities.shape == (300, 3) and np.flatnonzero(velocities.any(axis=1)).tolist() == [123]
    for objects, field in (
        ({"billboards": [dict(board, velocity=[0, "1", 0])]}, "billboards[0].velocity[1]"),
        ({"spheres": moving[:200] + [dict(moving[200], velocity=[0, 0])]}, "spheres[200].velocity"),
    ):
        with pytest.raises(SceneError) as info:
            scene_from_dict(scene_dict(**{"spheres": spheres, **objects}))
        assert info.value.field == field

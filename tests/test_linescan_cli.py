"""The line-scan commands, and bad 2D scenes: one line naming file and field, exit status 2,
no output file; the JSON Schema rejects exactly the structural errors."""

import copy
import json

import numpy as np
import pytest
from PIL import Image
from schemas import schema_validator

from conftest import SCENES, delete_field, set_field
from raykit.cli import main
from raykit.io.errors import SceneError
from raykit.io.images import quantize
from raykit.io.linescan_json import load_line_scene
from raykit.linescan.scan import scan, sweep

SCHEMA = schema_validator("linescan-v1.schema.json")
SCENE = {
    "camera": {"e": [0, 0], "w": [1, 0], "fov_angle": 60, "pixels": 16},
    "balls": [{"center": [5, 0], "radius": 1, "color": [1, 0, 0]}],
    "billboards": [{"start": [3, 1], "end": [3, 3], "color": [0, 1, 0]}],
}

# (id, mutation, field named in the message, words in the message, the schema rejects it too)
CASES = [
    ("missing field", delete_field("camera.w"), "camera.w", "required field is missing", True),
    ("mistyped field", set_field("camera.fov", 60), "camera.fov", 'did you mean "fov_angle"', True),
    (
        "wrong type",
        set_field("camera.pixels", "many"),
        "camera.pixels",
        "must be a whole number",
        True,
    ),
    (
        "wrong length",
        set_field("camera.e", [0, 0, 0]),
        "camera.e",
        "must have 2 numbers, got 3",
        True,
    ),
    ("NaN", set_field("balls.0.center", [float("nan"), 0]), "balls[0].center[0]", "got NaN", False),
    (
        "radius <= 0",
        set_field("balls.0.radius", -1),
        "balls[0].radius",
        "must be > 0, got -1",
        True,
    ),
    (
        "fov out of range",
        set_field("camera.fov_angle", 190),
        "camera.fov_angle",
        "must be < 180",
        True,
    ),
    ("pixels absurd", set_field("camera.pixels", 10**6), "camera.pixels", "must be <= 16384", True),
    ("w zero", set_field("camera.w", [0, 0]), "camera.w", "zero vector", False),
    (
        "segment of no length",
        set_field("billboards.0.end", [3, 1]),
        "billboards[0].end",
        "coincides with start",
        False,
    ),
    (
        "both image and color",
        set_field("billboards.0.image", "x.png"),
        "billboards[0]",
        "exactly one",
        True,
    ),
    (
        "row without image",
        set_field("billboards.0.row", 0),
        "billboards[0].row",
        'only for billboards with an "image"',
        True,
    ),
    (
        "row past the image",
        set_field("billboards", [{"start": [3, 1], "end": [3, 3], "image": "row.png", "row": 1}]),
        "billboards[0].row",
        "must be <= 0",
        False,
    ),
    (
        "texture missing",
        set_field("billboards", [{"start": [3, 1], "end": [3, 3], "image": "gone.png"}]),
        "billboards[0].image",
        "not found",
        False,
    ),
    (
        "velocity wrong type",
        set_field("balls.0.velocity", "fast"),
        "balls[0].velocity",
        "list of 2 numbers",
        True,
    ),
    ("scans zero", set_field("scans", 0), "scans", "must be >= 1", True),
]


@pytest.fixture
def folder(tmp_path):
    Image.new("RGBA", (4, 1), (9, 9, 9, 255)).save(tmp_path / "row.png")
    return tmp_path


@pytest.mark.parametrize(
    ("mutate", "field", "words"), [c[1:4] for c in CASES], ids=[c[0] for c in CASES]
)
@pytest.mark.parametrize("command", ["scan", "sweep"])
def test_bad_2d_scene_gets_one_line_exit_2_and_no_output(
    folder, capsys, command, mutate, field, words
):
    scene = copy.deepcopy(SCENE)
    mutate(scene)
    path = folder / "scene.json"
    path.write_text(json.dumps(scene))
    with pytest.raises(SceneError):
        load_line_scene(path)
    out = folder / "out.png"
    assert main([command, str(path), "-o", str(out), "--diagram", str(folder / "d.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith(f"raykit: error: {path}: {field}: ") and words in err
    assert sorted(p.name for p in folder.iterdir()) == ["row.png", "scene.json"]


@pytest.mark.parametrize(
    ("mutate", "schema_rejects"), [(c[1], c[4]) for c in CASES], ids=[c[0] for c in CASES]
)
def test_json_schema_rejects_exactly_the_structural_errors(mutate, schema_rejects):
    scene = copy.deepcopy(SCENE)
    mutate(scene)
    errors = list(SCHEMA.iter_errors(scene))
    assert bool(errors) == schema_rejects


def test_schema_accepts_every_example_line_scan_scene():
    for path in sorted((SCENES / "linescan").glob("*.json")):
        SCHEMA.validate(json.loads(path.read_text()))
        load_line_scene(path)


def test_scan_writes_the_strip_and_the_diagram(tmp_path, capsys):
    strip, rays = tmp_path / "strip.png", tmp_path / "rays.png"
    scene_file = SCENES / "linescan/slide.json"
    assert (
        main(["scan", str(scene_file), "-o", str(strip), "--diagram", str(rays), "--height", "5"])
        == 0
    )
    assert capsys.readouterr().out.startswith(f"wrote {strip} (12 pixels) and {rays} in ")
    pixels = np.asarray(Image.open(strip))
    expected = quantize(scan(load_line_scene(scene_file)).colors)
    assert pixels.shape == (5, 12, 3)
    assert (pixels == expected[None]).all()
    assert Image.open(rays).size[0] > 300


def test_scan_scale_draws_each_pixel_as_a_k_by_k_block(tmp_path):
    strip = tmp_path / "strip.png"
    scene_file = SCENES / "linescan/slide.json"
    assert main(["scan", str(scene_file), "-o", str(strip), "--height", "2", "--scale", "3"]) == 0
    pixels = np.asarray(Image.open(strip))
    expected = quantize(scan(load_line_scene(scene_file)).colors)
    assert pixels.shape == (6, 36, 3)
    for i in range(12):  # pixel i is the block of columns 3i to 3i + 2, in every row
        assert (pixels[:, 3 * i : 3 * i + 3] == expected[i]).all()


def test_sweep_writes_m_by_n_image(tmp_path, capsys):
    out = tmp_path / "sweep.png"
    scene_file = SCENES / "linescan/conveyor.json"
    assert main(["sweep", str(scene_file), "-o", str(out), "--scans", "40"]) == 0
    assert "(40 scans x 192 pixels)" in capsys.readouterr().out
    image = np.asarray(Image.open(out))
    assert np.array_equal(image, quantize(sweep(load_line_scene(scene_file), 40).image))

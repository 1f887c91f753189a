"""The reference's results (raykit_grading.assignment.references): a test's draw run by the
reference task, under the seed or the public draw, its textures read where the child would read
them; with a classic mistake made, the results the mistake gives, for the array tests and for
the pictures (made while the reference renders, and after)."""

from __future__ import annotations

import shutil

import numpy as np

from conftest import SCENES, scene_dict
from raykit_grading.assignment.catalog import STAGE3, VISIBLE, GradingTest, by_name
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.assignment.references import array_mistakes, expected, reference_results
from raykit_grading.kit.tasks import TASKS

SEED = 5858


def _test(number: str) -> GradingTest:
    return by_name([number])[0]


def _same(got: dict, want: dict) -> bool:
    return got.keys() == want.keys() and all(
        np.array_equal(got[k], want[k], equal_nan=True) for k in want
    )


def test_expected_is_the_reference_task_on_the_seeds_draw_or_the_public_one():
    for number in ("1.1", "2.1"):  # pixel positions, ray-plane hits
        test = _test(number)
        for seed, (spec, arrays, _) in (
            (SEED, test.graded_inputs(SEED)),
            (None, test.public_inputs()),
        ):
            assert _same(expected(test.name, seed), TASKS[test.task](spec, arrays)), number
        assert not _same(expected(test.name, SEED), expected(test.name, None)), number


def test_a_scan_reads_its_textures_where_the_child_finds_them(tmp_path):
    """Test 1.6 scans a scene with a textured billboard: its public draw is the scan of the
    scene file as it is, and a graded draw's the scan of its files laid out as the sandbox
    lays them out in the child's work folder."""
    from raykit.io.linescan_json import load_line_scene
    from raykit.linescan.scan import scan

    test = _test("1.6")
    as_it_is = scan(load_line_scene(SCENES / "linescan/slide.json")).colors[None]
    assert np.array_equal(expected(test.name, None)["rgb"], as_it_is)
    spec, arrays, files = test.graded_inputs(SEED)
    assert list(files) == ["scene/textures/car_side.png"]
    for relative, source in files.items():
        (tmp_path / relative).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source, tmp_path / relative)
    in_the_child = TASKS[test.task]({**spec, "folder": str(tmp_path / spec["folder"])}, arrays)
    assert _same(expected(test.name, SEED), in_the_child)


def test_an_array_tests_mistake_gives_what_the_mistake_says():
    """Pixel positions at the pixels' left edges: every one half a pixel (1/N) to the left."""
    test = _test("1.1")
    right = expected(test.name, SEED)["x"]
    wrong = expected(test.name, SEED, "pixel_x_corners")["x"]
    np.testing.assert_allclose(wrong, right - 1 / len(right), rtol=0, atol=1e-12)
    corners = next(m for m in MISTAKES if m.key == "pixel_x_corners")
    said = {says: (results, where) for says, results, where in array_mistakes(test, SEED)}
    results, where = said[corners.says]
    assert where == "raykit/linescan/camera.py: pixel_x"
    assert np.array_equal(results["x"], wrong)


def test_a_pictures_mistake_is_made_while_it_renders_and_after():
    """u and v swapped is made in the camera as it renders; rows counted from the bottom, by
    turning the right picture upside down."""
    scene = scene_dict(spheres=[{"center": [0.9, 0.4, 0], "radius": 0.7, "color": [1, 0, 0]}])
    test = GradingTest(
        "3.99 a small render", STAGE3, 1, VISIBLE, "render",
        lambda rng: ({"scene": scene, "folder": "scene"}, {}, {}), kind="image",
    )  # fmt: skip
    spec, arrays, files = test.public_inputs()
    right = reference_results(test, spec, arrays, files)["rgb"]
    flipped = reference_results(test, spec, arrays, files, "rows_flipped")["rgb"]
    assert np.array_equal(flipped, right[::-1]) and not np.array_equal(flipped, right)
    swapped = reference_results(test, spec, arrays, files, "u_v_swapped")["rgb"]
    assert swapped.shape == right.shape and not np.array_equal(swapped, right)
    assert np.array_equal(reference_results(test, spec, arrays, files)["rgb"], right)  # undone

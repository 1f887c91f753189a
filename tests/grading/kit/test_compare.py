"""What a student is told when a test fails (raykit_grading.kit.compare): array tests show inputs
and plain numbers and name the classic mistake of the function; renders name the mistake with the
percentages the score comes from; hidden tests say only the grader's words; the self-check page
and Gradescope's HTML come from one function. (The same, graded end to end through the sandbox:
grading/test_grade.py; through the kit's check.py: test_selfcheck.py.)"""

import re

import numpy as np
import pytest

from mistake_table import NAMED_IN
from raykit_grading.assignment.catalog import TESTS, by_name
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.assignment.references import array_mistakes, expected
from raykit_grading.kit.compare import (
    check_arrays,
    compare_images,
    feedback_html,
    feedback_picture,
    judge_arrays,
    judge_image,
    picture_scale,
    strict_fraction,
)

SEED = 20260101
ARRAY_CASES = [
    (key, number)
    for key, numbers in NAMED_IN.items()
    for number in numbers
    if by_name([number])[0].kind == "arrays"
]


def _test(number):
    return by_name([number])[0]


def _mistake(key):
    return next(m for m in MISTAKES if m.key == key)


def test_pixel_corners_in_pixel_x_are_shown_as_plain_numbers_with_the_input_and_named():
    test = _test("1.1")
    spec, arrays, _ = test.graded_inputs(SEED)
    got = expected(test.name, SEED, "pixel_x_corners")
    verdict = judge_arrays(
        got, expected(test.name, SEED), spec=spec, arrays=arrays,
        mistakes=array_mistakes(test, SEED),
    )  # fmt: skip
    pixels = spec["pixels"]
    assert verdict.share == 0.0
    assert verdict.message.startswith(f"x: {pixels} of {pixels} values differ")
    assert "np.float64" not in verdict.message and "array(" not in verdict.message
    assert "  x[0]: yours -1, expected " in verdict.message
    assert f"Inputs: pixels = {pixels}" in verdict.message
    assert f"off by the same amount, {-1 / pixels:.10g}" in verdict.message
    assert f"when {_mistake('pixel_x_corners').says} (made in raykit/linescan/camera.py: " \
        "pixel_x); it explains 100% of the values that differ" in verdict.message  # fmt: skip


@pytest.mark.parametrize("key, number", ARRAY_CASES, ids=[f"{k}-{n}" for k, n in ARRAY_CASES])
def test_each_array_mistake_is_named_in_the_test_of_its_function(key, number):
    test = _test(number)
    got = expected(test.name, SEED, key)
    verdict = judge_arrays(got, expected(test.name, SEED), mistakes=array_mistakes(test, SEED))
    assert verdict.share == 0.0
    named = [m.key for m in MISTAKES if f"when {m.says} (made in" in verdict.message]
    assert named == [key], verdict.message


def test_right_results_name_no_mistake_and_pass():
    for test in TESTS:
        if test.kind == "arrays":
            want = expected(test.name, SEED)
            verdict = judge_arrays(want, want, mistakes=array_mistakes(test, SEED))
            assert verdict.share == 1.0 and "Diagnosis" not in verdict.message, test.name


def test_a_callee_that_differs_is_named_as_where_the_difference_starts():
    right = {"u": np.array([1.0, 0, 0])}
    wrong = {"u": np.array([0.0, 1, 0])}
    verdict = judge_arrays(
        {"d": np.ones(2)}, {"d": np.zeros(2)},
        callees=[("camera_frame", right, right), ("_in_plane", wrong, right)],
        caller="rays_through",
    )  # fmt: skip
    assert "rays_through calls camera_frame and _in_plane; on this test's inputs _in_plane " \
        "already gives other results than the reference's, so the difference starts in " \
        "_in_plane." in verdict.message  # fmt: skip
    itself = judge_arrays(
        {"d": np.ones(2)}, {"d": np.zeros(2)}, callees=[("pixel_x", right, right)],
        caller="line_rays",
    )  # fmt: skip
    assert "so the difference starts in line_rays itself" in itself.message


def test_a_hidden_array_message_carries_nothing_the_submission_chose():
    want = {"t": np.array([1.0, 2.0, 3.0])}
    chosen = {"t": np.array([31337.25, 2.0, 3.0])}
    verdict = judge_arrays(chosen, want, spec={"radius": 0.123456}, arrays=want, hidden=True)
    assert verdict.share == 0.0
    assert "31337" not in verdict.message and "0.123456" not in verdict.message
    assert verdict.message.startswith("t: your values differ from the reference")
    shaped = judge_arrays({"t": np.zeros((4242, 1))}, want, hidden=True)
    assert "4242" not in shaped.message and shaped.message.startswith("t: not the result")
    visible = judge_arrays(chosen, want, spec={"radius": 0.123456}, arrays=want)
    assert "31337.25" in visible.message and "0.123456" in visible.message  # shown when visible


def _rgb(seed, shape=(30, 40)):
    return np.random.default_rng(seed).integers(0, 256, (*shape, 3)).astype(np.uint8)


def test_an_undiagnosed_render_states_the_percentage_its_score_comes_from():
    want = _rgb(1)
    mine = want.copy()
    mine[:2] = 255 - mine[:2]  # 2 of 30 rows wrong: 93.33% match
    verdict = judge_image(mine, want)
    fraction, share = re.search(
        r"([\d.]+)% of pixels match the reference, so this test gives (\d+)% of its points",
        verdict.message,
    ).groups()
    assert float(fraction) == pytest.approx(100 * 28 / 30, abs=0.005)
    assert verdict.share == pytest.approx((28 / 30 - 0.9) / 0.095)
    assert int(share) == round(100 * verdict.share)


def test_a_diagnosed_render_shows_no_percentage_that_contradicts_its_zero_score():
    want = _rgb(2)
    wrong = want[::-1].copy()
    verdict = judge_image(wrong, want, [("rows are flipped", wrong, "raykit/camera.py: x")])
    assert verdict.share == 0.0
    assert verdict.message.startswith(
        "Diagnosis: your image is what the renderer gives when rows are flipped (made in "
        "raykit/camera.py: x)."
    )
    assert "equals that mistake's picture in 100.0% of pixels" in verdict.message
    assert "gives 0% of its points" in verdict.message
    percentages = re.findall(r"([\d.]+)%", verdict.message)
    assert percentages[:2] == ["100.0", f"{np.mean((wrong == want).all(-1)):.1%}"[:-1]]


def test_a_named_mistake_wins_over_a_one_pixel_shift_that_fits_as_well():
    want = np.zeros((10, 12, 3), np.uint8)
    want[:, 6:] = 200
    moved = np.zeros_like(want)
    moved[:, 5:] = 200  # exactly the picture shifted one pixel left
    verdict = judge_image(moved, want, [("the pixel corners are used", moved, "pixel_x")])
    assert "when the pixel corners are used" in verdict.message
    assert "shifted by one pixel" not in verdict.message


def test_a_scan_strip_is_scaled_up_so_each_pixel_can_be_seen():
    assert picture_scale(1, 24) == (10, 40)  # a scan: 24 pixels, one row
    assert picture_scale(160, 40) == (3, 3)  # a sweep: no taller than 480
    assert picture_scale(240, 320) == (1, 1)
    strip = _rgb(3, (1, 24))
    picture = judge_image(255 - strip, strip).picture
    assert picture.shape[1] == 3 * 240 + 2 * 6 and picture.shape[0] >= 40


def test_feedback_html_wraps_and_keeps_pixels_sharp():
    page = feedback_html("a <b> line\nand another", "data:image/png;base64,AAAA")
    assert "white-space: pre-wrap" in page and "overflow-wrap: anywhere" in page
    assert "a &lt;b&gt; line" in page
    assert "max-width: 100%" in page and "image-rendering: pixelated" in page


@pytest.mark.slow
def test_image_comparison_forgives_a_silhouette_pixel_but_not_a_wrong_colour():
    reference = np.zeros((20, 20, 3), np.uint8)
    reference[5:15, 5:15] = 200
    shifted_edge = reference.copy()
    shifted_edge[5, 5:15] = 0  # the silhouette one pixel in
    assert compare_images(shifted_edge, reference).fraction == 1.0
    assert strict_fraction(shifted_edge, reference) < 1.0
    recoloured = reference.copy()
    recoloured[5:15, 5:15] = 150
    result = compare_images(recoloured, reference)
    assert result.fraction == pytest.approx(1 - 100 / 400)  # no neighbour has the new colour
    assert result.score() == 0.0
    assert np.isfinite(result.psnr) and result.psnr < 30
    picture = feedback_picture(recoloured, reference, result.matched)
    # each panel drawn 12 times larger (a small image made visible), captions above
    assert picture.shape == (240 + 22, 3 * 240 + 2 * 6, 3) and picture.dtype == np.uint8


@pytest.mark.slow
def test_score_is_linear_between_the_thresholds():
    from raykit_grading.kit.compare import Comparison

    assert Comparison(None, 0.995, 0).score() == 1.0
    assert Comparison(None, 0.9475, 0).score() == pytest.approx(0.5)
    assert Comparison(None, 0.89, 0).score() == 0.0


@pytest.mark.slow
def test_array_check_accepts_nan_or_inf_for_a_miss_and_names_the_first_difference():
    want = {"t": np.array([1.0, np.inf, 2.0])}
    assert check_arrays({"t": np.array([1.0, np.nan, 2.0])}, want)[0]
    ok, message = check_arrays({"t": np.array([1.0, np.inf, 2.5])}, want)
    assert (
        not ok and "t: 1 of 3 values differ" in message and "t[2]: yours 2.5, expected 2" in message
    )
    assert not check_arrays({"t": np.ones(4)}, want)[0]
    assert not check_arrays({"t": np.array(["a", "b", "c"])}, want)[0]

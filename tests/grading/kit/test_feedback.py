"""What a student is told when a test fails: array tests show inputs and plain numbers and name
the classic mistake of the function; renders name the mistake with the percentages the score
comes from; hidden tests say only the grader's words; the self-check page and Gradescope's
HTML come from one function. (The same, graded end to end through the sandbox:
test_feedback_graded.py.)"""

import re

import numpy as np
import pytest

from mistake_table import NAMED_IN
from raykit_grading.assignment.catalog import TESTS, VISIBLE, by_name
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.assignment.references import array_mistakes, expected
from raykit_grading.kit.compare import (
    feedback_html,
    judge_arrays,
    judge_image,
    picture_scale,
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


def test_the_self_check_page_starts_with_the_summary_and_lists_failures_first(monkeypatch):
    import importlib
    import sys

    import raykit_grading
    from raykit_grading.kit import cases, compare, tasks

    monkeypatch.setattr(sys, "path", list(sys.path))  # check.py puts its folders first
    # check.py imports the grader's modules as the release's tests/_grading package
    for name, module in {"": raykit_grading, ".cases": cases, ".tasks": tasks,
                         ".compare": compare}.items():  # fmt: skip
        monkeypatch.setitem(sys.modules, f"_grading{name}", module)
    monkeypatch.delitem(sys.modules, "raykit_grading.kit.selfcheck", raising=False)
    page = importlib.import_module("raykit_grading.kit.selfcheck").page

    rows = [
        {"name": "1.1 a", "points": 1, "share": 1.0, "message": "ok", "picture": None},
        {"name": "1.3 b", "points": 2, "share": 0.0, "message": "x: differs", "picture": None},
        {"name": "3.6 c", "points": 4, "share": 0.5, "message": "half", "picture": "3_6.png"},
    ]
    text = page(rows)
    assert text.index("1 of 3 practice tests pass: 3 of 7 points") < text.index("FAIL: 1.3 b")
    assert text.index("FAIL: 1.3 b") < text.index("FAIL: 3.6 c") < text.index("pass: 1.1 a")
    assert "2 of 4 points" in text and feedback_html("half", "3_6.png") in text
    assert "name='viewport'" in text


def test_every_visible_array_test_with_a_callee_names_it():
    for test in TESTS:
        if test.task in ("rays_through", "line_rays"):
            assert test.callees, test.name
    assert any(t.visibility == VISIBLE and t.callees for t in TESTS)


def test_every_mistake_is_blamed_on_a_function_the_student_writes():
    """``where`` names the functions the release leaves to write (its stubs), never given code
    a student function calls (such as Camera.plane_size, read by _in_plane)."""
    from raykit_grading.assignment.catalog import REPO
    from raykit_grading.assignment.markers import strip_solutions

    stubs = set()
    for source in (REPO / "raykit").rglob("*.py"):
        names = strip_solutions(source.read_text(), str(source))[1]
        stubs |= {f"{source.relative_to(REPO)}: {name}" for name in names}
    for mistake in MISTAKES:
        named = re.findall(r"(raykit/[\w/]+\.py: [\w.]+)", mistake.where)
        assert named and set(named) <= stubs, (mistake.key, named)


def test_the_summary_shown_at_once_sums_the_visible_tests_and_tells_no_hidden_outcome():
    """Two results that differ only in how the hidden tests went (all passed, all failed)
    give the same summary: the visible tests' sums, then the hidden tests' count and points."""
    from raykit_grading.grading.results import stage_lines, test_entry

    tests = by_name(["2.1", "2.3", "2.4", "2.5", "3.6", "3.8"])
    passed = [test_entry(t, t.points, "") for t in tests]
    failed = [e if t.visibility == VISIBLE else test_entry(t, 0.0, "") for t, e in
              zip(tests, passed, strict=True)]  # fmt: skip
    assert (
        stage_lines(tests, passed)
        == stage_lines(tests, failed)
        == [
            "Stage 2 rays, planes and spheres: 4 of 4 points, 2 of 2 visible tests pass",
            "Stage 3 renderer: 4 of 4 points, 1 of 1 visible tests pass",
            "Hidden tests: 3, 5 points (how they went is not shown here)",
        ]
    )

"""The feedback end to end: each classic mistake, made in the one function where students make
it, graded through the sandbox and through the release's check.py, is named in the test of
that function (and in a render that shows it), no other mistake is named, and every message's
percentages are the ones its score comes from. Hidden tests carry nothing a hostile submission
chose into their messages."""

import html
import re

import pytest

from mistake_table import NAMED_IN, _says
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import by_name
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.grading.grade import Options, grade

pytestmark = pytest.mark.slow
SEED = 3
FAIR = re.compile(r"([\d.]+)% of pixels match the reference, so this test gives (\d+)% of")


def _where(key):
    return next(m.where for m in MISTAKES if m.key == key)


def _text(output: str) -> str:
    return html.unescape(re.sub(r"<[^>]+>", "", output))


@pytest.mark.parametrize("key", sorted(NAMED_IN))
def test_each_mistake_is_named_in_its_functions_test_with_the_scores_percentages(
    key, tmp_path, child_python
):
    submission = make_submission(tmp_path / "submission", key)
    results = grade(submission, names=NAMED_IN[key], options=Options(child_python), seed=SEED)
    assert [t["number"] for t in results["tests"]] == NAMED_IN[key]
    made_in = [
        name.split(": ")[1] for name in re.findall(r"raykit/[\w/]+\.py: [\w.]+", _where(key))
    ]
    for entry in results["tests"]:
        text = _text(entry["output"])
        assert f"when {_says(key)}" in text, (entry["number"], text)
        # the function the mistake was planted in, which the student writes, is named
        assert any(name in text for name in made_in), (entry["number"], made_in, text)
        assert "plane_size" not in text and "sample_offsets" not in text
        others = [m.key for m in MISTAKES if m.key != key and f"when {m.says}" in text]
        assert others == [], (entry["number"], others)
        assert entry["score"] == 0.0
        if by_name([entry["number"]])[0].kind == "image":
            assert FAIR.search(text) is None  # no "100% match" beside a score of 0
            assert "this test gives 0% of its points" in text


def test_an_imperfect_render_states_the_percentage_its_score_comes_from(tmp_path, child_python):
    submission = make_submission(tmp_path / "submission")
    lambert = submission / "raykit/shading.py"  # a slightly wrong brightness: rounding-sized
    source = lambert.read_text()
    assert source.count("return kd * intensity *") == 1
    lambert.write_text(source.replace("return kd * intensity *", "return 0.985 * kd * intensity *"))
    results = grade(submission, names=["4.8"], options=Options(child_python), seed=SEED)
    entry = results["tests"][0]
    fraction, share = FAIR.search(_text(entry["output"])).groups()
    expected = min(1.0, max(0.0, (float(fraction) / 100 - 0.9) / 0.095))
    assert entry["score"] / entry["max_score"] == pytest.approx(expected, abs=0.001)
    assert int(share) == round(100 * entry["score"] / entry["max_score"])


# A hostile pixel_x, graded on visible 1.1 and hidden 1.2: what it chose (a member name, a
# shape, values, an error message) reaches 1.1's message (so each attack works) and never
# 1.2's.
SMUGGLERS = {
    "member name": (
        "    import io, json, os, sys, zipfile\n"
        "    from pathlib import Path\n"
        "    order = json.loads((Path(sys.argv[1]) / 'task.json').read_text())\n"
        "    packed = io.BytesIO()\n"
        "    with zipfile.ZipFile(packed, 'w') as z:\n"
        "        z.writestr(f'SMUGGLED{pixels}x{samples}.txt', 'x')\n"
        "    os.write(order['outputs_fd'], packed.getvalue())\n"
        "    os._exit(0)\n"
    ),
    "shape": "    return np.zeros((pixels * samples, 4242))\n",
    "values": "    return np.full(pixels * samples, 313370.0 + samples)\n",
    "error message": "    raise ValueError(f'SMUGGLED{pixels}x{samples}')\n",
}
FINGERPRINTS = {"member name": "SMUGGLED", "shape": "4242", "values": "31337",
                "error message": "SMUGGLED"}  # fmt: skip


@pytest.mark.parametrize("attack", sorted(SMUGGLERS))
def test_a_hidden_test_carries_nothing_the_submission_chose(attack, tmp_path, child_python):
    submission = make_submission(tmp_path / "submission")
    camera = submission / "raykit/linescan/camera.py"
    source = camera.read_text()
    body = "    i = np.repeat(np.arange(pixels), samples)\n"
    assert source.count(body) == 1
    camera.write_text(source.replace(body, SMUGGLERS[attack] + body))
    results = grade(submission, names=["1.1", "1.2"], options=Options(child_python), seed=SEED)
    visible, hidden = results["tests"]
    assert visible["score"] == hidden["score"] == 0.0
    assert FINGERPRINTS[attack] in visible["output"]  # the attack reaches a visible message
    assert FINGERPRINTS[attack] not in hidden["output"], hidden["output"]
    assert "hidden test" in hidden["output"]

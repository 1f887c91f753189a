"""Grading one submission (raykit_grading.grading.grade), through the sandbox: the solution
scores full marks, the student release 0; each classic mistake, made in the one function where
students make it, is named in the test of that function (and in a render that shows it), no
other mistake is named, and every message's percentages are the ones its score comes from;
hidden tests carry nothing a hostile submission chose into their messages; results.json follows
Gradescope's specification; without a clone (the wheel holds no hidden scenes) it says so."""

import html
import json
import re

import jsonschema
import pytest
import tomllib

from conftest import REPO
from mistake_table import NAMED_IN, _says
from mistaken_submissions import EDITS, make_rewritten, make_submission
from raykit_grading.assignment.catalog import TESTS, VISIBLE, by_name
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.grading.grade import Options, grade, grade_to_file

# Gradescope's results.json, as its autograder specification documents it
RESULTS_SCHEMA = {
    "type": "object",
    "required": ["tests"],
    "properties": {
        "score": {"type": "number"},
        "execution_time": {"type": "number"},
        "output": {"type": "string"},
        "visibility": {"enum": ["hidden", "after_due_date", "after_published", "visible"]},
        "stdout_visibility": {"enum": ["hidden", "after_due_date", "after_published", "visible"]},
        "extra_data": {"type": "object"},
        "tests": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["score", "max_score", "name", "output", "visibility"],
                "properties": {
                    "score": {"type": "number"},
                    "max_score": {"type": "number"},
                    "status": {"enum": ["passed", "failed"]},
                    "name": {"type": "string"},
                    "number": {"type": "string"},
                    "output": {"type": "string"},
                    "tags": {"type": "array", "items": {"type": "string"}},
                    "visibility": {
                        "enum": ["hidden", "after_due_date", "after_published", "visible"]
                    },
                },
            },
        },
    },
}
TOTAL = sum(t.points for t in TESTS)


def test_solution_scores_full_marks_in_a_valid_results_file(solution, child_python, tmp_path):
    status = grade_to_file(
        solution,
        tmp_path / "results.json",
        options=Options(child_python),
        feedback=tmp_path / "feedback",
    )
    assert status == 0
    written = results = json.loads((tmp_path / "results.json").read_text())
    jsonschema.validate(written, RESULTS_SCHEMA)
    failed = [(t["name"], t["output"]) for t in written["tests"] if t["score"] < t["max_score"]]
    assert failed == []
    assert results["score"] == pytest.approx(TOTAL)
    assert {t["visibility"] for t in written["tests"]} == {"visible", "after_due_date"}
    assert len(list((tmp_path / "feedback").glob("*.png"))) == sum(t.kind == "image" for t in TESTS)


def test_execution_time_ends_at_the_last_visible_test(tmp_path, monkeypatch):
    """execution_time is shown at once: it stops where the hidden tests start, so how long they
    ran (a hidden input that makes the code loop) never shows before the due date. The grader's
    clock here is one that each test advances, 1 s a visible test, 100 s a hidden one."""
    import types

    from raykit_grading.grading import grade as grading
    from raykit_grading.grading.results import test_entry

    now = [0.0]

    class Sandbox:  # what grade asks of one, running nothing
        description = "none: a test's stand-in"

        def oom_count(self) -> None:
            return None

    def graded(sandbox, test, *args):
        now[0] += 1.0 if test.visibility == VISIBLE else 100.0
        return test_entry(test, test.points, "")

    monkeypatch.setattr(grading, "choose_sandbox", lambda *args: Sandbox())
    monkeypatch.setattr(grading, "_import_error", lambda *args: ("", []))
    monkeypatch.setattr(grading, "_grade_one", graded)
    clock = types.SimpleNamespace(perf_counter=lambda: now[0], monotonic=lambda: now[0])
    monkeypatch.setattr(grading, "time", clock)
    (tmp_path / "raykit").mkdir()
    (tmp_path / "raykit" / "__init__.py").write_text("")
    results = grade(tmp_path, names=["2.4", "2.3", "2.5", "2.6"])  # 2.4, 2.5 hidden
    assert [t["number"] for t in results["tests"]] == ["2.3", "2.4", "2.5", "2.6"]
    assert now[0] == 202.0 and results["execution_time"] == 2.0


def test_grader_scores_the_bare_release_zero_and_says_what_to_write(release, child_python):
    results = grade(release, options=Options(child_python))
    assert results["score"] == 0
    assert all(t["output"].startswith("not written yet") for t in results["tests"])
    visible = [t["output"] for t in results["tests"] if t["visibility"] == "visible"]
    assert any("/submission/raykit/" in output for output in visible)  # where it stopped
    assert not any("child.py" in output or "tasks.py" in output for output in visible)


def test_submission_without_a_package_scores_zero(tmp_path, child_python):
    (tmp_path / "notes.txt").write_text("oops")
    results = grade(tmp_path, options=Options(child_python))
    assert results["score"] == 0 and "no raykit package" in results["tests"][0]["output"]


@pytest.mark.parametrize(
    "key", sorted(k for k in EDITS if next(m for m in MISTAKES if m.key == k).in_renders)
)
def test_each_classic_mistake_is_named_in_the_feedback(key, tmp_path, child_python):
    submission = make_submission(tmp_path, key)
    mistake = next(m for m in MISTAKES if m.key == key)
    says = mistake.says
    names = {
        "1": ["1.6", "1.7"],  # a scan and a sweep of the line-scan camera
        "3": ["3.6", "3.8", "3.9", "3.11"],  # classic, parallel rays, inside a ring, overlaps
        "4": ["4.8", "4.10", "4.11"],  # lit classic, mirrors, at 1e6 with a touching ball
        "5": ["5.16", "5.17", "5.18", "5.19", "5.20"],  # light, lens, glossy, blur, hidden
    }[mistake.stage]
    results = grade(submission, options=Options(child_python), names=names)
    outputs = [html.unescape(t["output"]) for t in results["tests"]]
    assert any(f"when {says}" in out for out in outputs), outputs
    for out in outputs:  # no other mistake is named instead
        assert all(f"when {m.says}" not in out for m in MISTAKES if m.key != key)


STAGE5 = [t.key for t in TESTS if t.stage.startswith("5")]


def test_stage5_written_right_another_way_scores_in_full(tmp_path, child_python):
    # the renders' noise reaches pixels through the student's own jittered_point, point_in_pixel,
    # point_on_lens and sampled: rounded otherwise, the same picture within the comparison's
    # tolerance, under any seed
    submission = make_rewritten(tmp_path / "rewritten")
    for seed in (5, 2026):
        results = grade(submission, options=Options(child_python), names=STAGE5, seed=seed)
        failed = [(t["number"], t["output"]) for t in results["tests"]
                  if t["score"] < t["max_score"]]  # fmt: skip
        assert failed == []
        assert results["score"] == pytest.approx(sum(t.points for t in TESTS if t.key in STAGE5))


def test_no_mistake_is_named_for_the_solution(solution, child_python):
    names = ["3.6", "3.9", "3.11", "4.8", "4.10", "4.11", "5.16", "5.18", "5.19", "5.20"]
    results = grade(solution, options=Options(child_python), names=names)
    assert not any("Diagnosis:" in t["output"] for t in results["tests"])


def test_the_wheel_holds_raykit_and_its_grader_but_no_hidden_scenes():
    from setuptools import find_packages

    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages = find_packages(str(REPO), include=config["packages"]["find"]["include"])
    assert "grading" not in packages and "raykit_grading" in packages
    assert {p.split(".")[0] for p in packages} == {"raykit", "raykit_grading"}
    data = config.get("package-data", {})
    assert all("scenes" not in pattern for patterns in data.values() for pattern in patterns)
    assert not list((REPO / "raykit_grading").rglob("*.json"))


def test_the_grader_says_plainly_when_it_has_no_clone_to_read_scenes_from(monkeypatch, tmp_path):
    import raykit_grading.grading.grade as grade

    monkeypatch.setattr(grade, "HIDDEN_SCENES", tmp_path / "nowhere")
    with pytest.raises(grade.GradingImpossible, match="needs a clone of the course repository"):
        grade.check_clone()


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

"""The kit's check.py (raykit_grading.kit.selfcheck): its page, the one test asked for, each mistake
named as the grader names it."""

from __future__ import annotations

import html
import shutil
import subprocess
import sys

import pytest

from mistake_table import NAMED_IN, _says
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS, VISIBLE, by_name
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.kit.compare import feedback_html


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


@pytest.mark.slow
def test_release_self_check_judges_like_the_grader_and_draws_the_pictures(release, tmp_path):
    import shutil

    def check(key):
        copy = tmp_path / (key or "solution")
        shutil.copytree(release, copy)
        shutil.rmtree(copy / "raykit")
        make_submission(copy, key)
        return subprocess.run(
            [sys.executable, "check.py"],
            cwd=copy,
            capture_output=True,
            text=True,
            env={"PATH": "/usr/bin:/bin"},
        ), copy

    right, folder = check(None)
    assert right.returncode == 0, right.stdout[-2000:]
    visible = [t for t in TESTS if t.visibility == VISIBLE]
    assert f"{len(visible)} of {len(visible)} practice tests pass" in right.stdout
    pictures = sorted(p.name for p in (folder / "check").glob("*.png"))
    assert pictures == sorted(
        f"{t.key.replace('.', '_')}.png" for t in visible if t.kind == "image"
    )
    assert "<a href='3_6.png'>the picture</a>" in (folder / "check/index.html").read_text()
    wrong, _ = check("pixel_corners")
    assert wrong.returncode == 1
    assert "FAIL  3.6 render scenes/classic.json (320 x 240)" in wrong.stdout
    assert "rays go through pixel corners instead of pixel centres" in wrong.stdout


@pytest.mark.slow
def test_check_py_runs_the_one_test_asked_for_and_says_how_in_its_help(release, tmp_path):
    kit = tmp_path / "kit"
    shutil.copytree(release, kit)
    shutil.rmtree(kit / "raykit")
    make_submission(kit, "rows_flipped")
    env = {"PATH": "/usr/bin:/bin"}
    one = subprocess.run(
        [sys.executable, "check.py", "3.6"], cwd=kit, capture_output=True, text=True, env=env
    )
    said = [line for line in one.stdout.splitlines() if line.startswith(("pass", "FAIL"))]
    assert len(said) == 1 and said[0].startswith("FAIL  3.6 render scenes/classic.json")
    assert "0 of 1 practice tests pass" in one.stdout and one.returncode == 1
    stage = subprocess.run(
        [sys.executable, "check.py", "1"], cwd=kit, capture_output=True, text=True, env=env
    )
    visible = [t for t in TESTS if t.visibility == VISIBLE and t.key.startswith("1.")]
    assert f"{len(visible)} of {len(visible)} practice tests pass" in stage.stdout
    helped = subprocess.run(
        [sys.executable, "check.py", "--help"], cwd=kit, capture_output=True, text=True, env=env
    )
    assert helped.returncode == 0 and "python check.py 3.6" in helped.stdout
    assert not (kit / "check/index.html").read_text().count("FAIL: 1.")  # --help ran nothing
    wrong = subprocess.run(
        [sys.executable, "check.py", "9.9"], cwd=kit, capture_output=True, text=True, env=env
    )
    assert wrong.returncode == 2 and "no practice test 9.9: they are 1.1, " in wrong.stderr


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(NAMED_IN))
def test_the_self_check_names_each_mistake_in_its_visible_tests(key, release, tmp_path):
    visible = [n for n in NAMED_IN[key] if by_name([n])[0].visibility == VISIBLE]
    if not visible:
        pytest.skip(f"{key} shows only in hidden tests")
    copy = tmp_path / "student"
    shutil.copytree(release, copy)
    shutil.rmtree(copy / "raykit")
    make_submission(copy, key)
    run = subprocess.run(
        [sys.executable, "check.py"], cwd=copy, capture_output=True, text=True,
        env={"PATH": "/usr/bin:/bin"},
    )  # fmt: skip
    assert run.returncode == 1
    page = html.unescape((copy / "check/index.html").read_text())
    for number in visible:
        name = by_name([number])[0].name
        section = page.split(f"FAIL: {name}:")[1].split("<section")[0]
        assert f"when {_says(key)}" in section, (number, section)
        assert not [m.key for m in MISTAKES if m.key != key and f"when {m.says}" in section]
    assert page.index("practice tests pass") < page.index("FAIL:")

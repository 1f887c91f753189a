"""The student release (raykit_grading.assignment.release): what it holds and hides, its README and
pyproject, its own tests and its renderer, as a student meets them."""

from __future__ import annotations

import re
import subprocess
import sys

from conftest import REPO
from raykit_grading.assignment.catalog import HIDDEN_SCENES, TESTS, VISIBLE


def _student_pytest(folder):
    """The release's own test command, run in ``folder`` with its raykit first on the path."""
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "tests"],
        cwd=folder,
        capture_output=True,
        text=True,
        env={"PYTHONPATH": str(folder), "PATH": "/usr/bin:/bin", "COLUMNS": "400"},
    )


def test_release_imports_cleanly_and_its_stubs_raise(release):
    code = (
        "import importlib, pkgutil, raykit\n"
        "names = [m.name for m in pkgutil.walk_packages(raykit.__path__, 'raykit.')]\n"
        "[importlib.import_module(n) for n in names if 'diagrams' not in n and 'main' not in n]\n"
        "from raykit.planes import hit_plane\n"
        "import numpy as np\n"
        "try:\n    hit_plane(np.zeros((1, 3)), np.ones((1, 3)), np.zeros(3), np.ones(3))\n"
        "except NotImplementedError as e:\n    print('stub:', e)\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code],
        cwd=release,
        capture_output=True,
        text=True,
        env={"PYTHONPATH": str(release), "PATH": "/usr/bin:/bin"},
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("stub: hit_plane: write this function. Hint: t = ((a - o)·n)")


def test_release_visible_tests_fail_with_not_implemented_only(release):
    run = _student_pytest(release)
    visible = sum(t.visibility == VISIBLE for t in TESTS)
    assert f"{visible} failed" in run.stdout
    failures = [line for line in run.stdout.splitlines() if line.startswith("FAILED")]
    assert len(failures) == visible
    assert all("NotImplementedError" in line for line in failures), failures


def test_solution_dropped_into_the_release_passes_its_visible_tests(release, tmp_path):
    import shutil

    copy = tmp_path / "student"
    shutil.copytree(release, copy)
    shutil.rmtree(copy / "raykit")
    shutil.copytree(REPO / "raykit", copy / "raykit")
    run = _student_pytest(copy)
    assert run.returncode == 0, run.stdout[-2000:]


def test_release_hides_the_solutions_and_the_hidden_scenes(release):
    sources = "".join(p.read_text() for p in (release / "raykit").rglob("*.py"))
    assert "BEGIN SOLUTION" not in sources
    assert "(a - origins) @ n" not in sources  # the ray-plane solution line
    hidden = sorted(p.name for p in HIDDEN_SCENES.glob("*.json"))
    assert {"odd.json", "overlaps.json", "lens_and_panel.json"} <= set(hidden)
    assert not [name for name in hidden if list(release.rglob(name))]
    assert (release / "tests/expected/3_6/reference.png").is_file()


def test_release_readme_lists_the_functions_in_the_lectures_order(release):
    listed = [
        line
        for line in (release / "README.md").read_text().splitlines()
        if line.startswith("- `raykit/")
    ]
    names = [line.split(": ")[1].rstrip("`") for line in listed]
    assert names[0] == "pixel_x" and names[-1] == "center_at"
    assert names.index("hit_plane") < names.index("camera_frame") < names.index("cast")
    assert names.index("cast") < names.index("lambert") < names.index("reflect")
    # stage 5 in FOCG 13.4's order, its camera and light functions among the sample patterns
    stage5 = names[names.index("reflect") + 1 :]
    assert stage5[:4] == ["point_in_pixel", "random_set", "jittered_point", "jittered_set"]
    assert stage5.index("sampled") < stage5.index("point_on_lens") < stage5.index("thin_lens_rays")
    assert stage5.index("thin_lens_rays") < stage5.index("basis_around")
    assert stage5[-5:] == [
        "basis_around",
        "perturbed_direction",
        "glossy_reflect",
        "shutter_times",
        "center_at",
    ]


def test_release_pyproject_carries_only_what_the_release_uses(release):
    import tomllib

    project = tomllib.loads((release / "pyproject.toml").read_text())
    assert project["project"]["optional-dependencies"] == {"test": ["pytest>=7.4"]}
    kit = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    assert project["project"]["dependencies"] == kit["dependencies"]
    assert "ruff" not in project.get("tool", {}) and "nbval" not in str(project)


def test_release_render_names_the_function_to_write_next_in_one_line(release, tmp_path):
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "raykit",
            "render",
            "scenes/classic.json",
            "-o",
            str(tmp_path / "c.png"),
        ],
        cwd=release,
        capture_output=True,
        text=True,
        env={"PYTHONPATH": str(release), "PATH": "/usr/bin:/bin"},
    )
    assert run.returncode == 2
    assert run.stderr.startswith("raykit: error: not written yet: ")
    assert "write this function" in run.stderr and run.stderr.count("\n") == 1
    assert not (tmp_path / "c.png").exists()


def test_the_kits_pytest_prints_one_line_per_failing_test(release):
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider"],
        cwd=release, capture_output=True, text=True,
        env={"PYTHONPATH": str(release), "PATH": "/usr/bin:/bin", "COLUMNS": "100"},
    )  # fmt: skip
    visible = sum(t.visibility == VISIBLE for t in TESTS)
    lines = run.stdout.splitlines()
    failed = [line for line in lines if line.startswith("FAILED")]
    assert len(failed) == visible and "Traceback" not in run.stdout
    assert len(lines) < visible + 15, run.stdout  # the header, the summary, and those lines


def test_the_kits_readme_lists_the_functions_under_each_stage(release):
    readme = (release / "README.md").read_text()
    headings = re.findall(r"^### (.*)$", readme, re.M)
    assert headings[:5] == [
        "Stage 1 line-scan camera", "Stage 2 rays, planes and spheres", "Stage 3 renderer",
        "Stage 4 shading, shadows and mirrors", "Stage 5 distributed ray tracing",
    ]  # fmt: skip
    stage3 = readme.split("### Stage 3")[1].split("###")[0]
    assert "camera.py: camera_frame`" in stage3 and "hit_sphere" not in stage3
    assert "python check.py 3.6" in readme


def test_the_starter_kits_compiled_engine_says_what_the_kit_can_do_instead(release, tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "raykit.cli", "render", "scenes/classic.json", "-o",
         str(tmp_path / "x.png"), "--engine", "compiled"],
        cwd=release, capture_output=True, text=True,
        env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(release)},
    )  # fmt: skip
    assert run.returncode == 2
    assert run.stderr.strip().splitlines() == [
        "raykit: error: --engine compiled is not in the starter kit (it would give the "
        "solutions away): render with your own functions, --engine numpy (what auto picks "
        "here); for a quicker look, make the picture smaller (the camera's width and height "
        "in the scene file)"
    ]
    assert "raykit[fast]" not in run.stderr and not (tmp_path / "x.png").exists()

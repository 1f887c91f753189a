"""The benchmarks run and print their tables (their figures are for people, not assertions)."""

import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO


def _table_rows(script: str) -> list[str]:
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks" / script), "--quick", "--repeats", "1"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    tables = [t.splitlines() for t in run.stdout.split("\n\n")]
    first = next(t for t in tables if t and t[0].startswith("| "))
    return [line for line in first if line.startswith("| ")][1:]  # the first table's rows


def test_render_speed_quick_prints_a_row_per_scene_with_every_variant():
    rows = _table_rows("render_speed.py")
    assert [row.split(" | ")[0] for row in rows] == [
        "| classic",
        "| sphereflake 2",
        "| 100 spheres",
    ]
    assert all(row.count(" ms") + row.count(" s ") >= 3 for row in rows)


def test_render_speed_compares_float32_with_float64():
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks/render_speed.py"), "--quick", "--repeats", "1"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    table = run.stdout.split("| scene | float64 | float32")[1]
    examples = len(list((REPO / "scenes").glob("*.json")))
    assert table.count(" of ") == 3 + examples  # the benchmark scenes and every example scene


def test_time_vs_error_quick_prints_every_mode():
    rows = _table_rows("time_vs_error.py")
    assert len(rows) == 7
    assert sum("adaptive" in row for row in rows) == 3


def test_raykit_bench_runs_every_benchmark_and_writes_the_plots(tmp_path):
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "raykit",
            "bench",
            "--quick",
            "--repeats",
            "1",
            "--plots",
            str(tmp_path),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.count("$ python benchmarks/") == 4
    assert "| mirror_balls |" in run.stdout and "| level 2 |" in run.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "time_vs_error.png",
        "time_vs_objects.png",
    ]


def test_mitsuba_comparison_times_raykit_and_mitsuba_when_installed():
    rows = _table_rows("mitsuba_compare.py")
    renderers = [row.split(" | ")[1] for row in rows]
    assert renderers.count("raykit") == 2
    try:
        import mitsuba  # noqa: F401
    except ImportError:
        return  # an optional benchmark dependency: raykit alone is timed
    assert sum(r.startswith("Mitsuba") for r in renderers) == 4


def test_billboard_becomes_a_mitsuba_rectangle_with_the_same_corners():
    mi = pytest.importorskip("mitsuba")
    sys.path.insert(0, str(REPO / "benchmarks"))
    from mitsuba_compare import mitsuba_dict

    mi.set_variant("scalar_rgb")
    board = {"upper_left": [1.0, 3, -2], "lower_left": [0.5, 0, -2.5], "upper_right": [4, 3.5, -1]}
    camera = {
        "eye": [0, 1, 6],
        "lookat": [0, 1, 0],
        "up": [0, 1, 0],
        "fov_angle": 40,
        "width": 8,
        "height": 6,
    }
    made = mitsuba_dict({"camera": camera, "spheres": [], "billboards": [board]}, mi)
    to_world = made["billboard0"]["to_world"]
    for corner, (x, y) in (
        ("upper_left", (-1, -1)),
        ("upper_right", (1, -1)),
        ("lower_left", (-1, 1)),
    ):
        point = to_world @ mi.ScalarPoint3f(x, y, 0)
        np.testing.assert_allclose(np.array(point), board[corner], atol=1e-5)


def test_object_order_quick_prints_a_row_per_object_count():
    rows = _table_rows("object_order.py")
    assert [row.split(" | ")[0] for row in rows] == ["| 1", "| 10", "| 100"]
    assert all(row.count(" ms") + row.count(" s ") >= 3 for row in rows)


def test_forward_backward_quick_prints_both_directions():
    rows = _table_rows("forward_backward.py")
    directions = [row.split(" | ")[0] for row in rows]
    assert directions == ["| backward"] * 2 + ["| forward"] * 2

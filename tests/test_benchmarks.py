"""The benchmarks run and print their tables (their figures are for people, not assertions)."""

import subprocess
import sys

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
    assert run.stdout.count("$ python benchmarks/") == 3
    assert "| mirror_balls |" in run.stdout and "| level 2 |" in run.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "time_vs_error.png",
        "time_vs_objects.png",
    ]

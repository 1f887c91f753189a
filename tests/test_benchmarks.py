"""The benchmark runs and prints its table (its figures are for people, not assertions)."""

import subprocess
import sys

from conftest import REPO


def test_render_speed_quick_prints_a_row_per_scene_with_every_variant():
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks/render_speed.py"), "--quick", "--repeats", "1"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    rows = [line for line in run.stdout.splitlines() if line.startswith("| ")][1:]
    assert [row.split(" | ")[0] for row in rows] == [
        "| classic",
        "| sphereflake 2",
        "| 100 spheres",
    ]
    assert all(row.count(" ms") + row.count(" s ") >= 3 for row in rows)


def test_time_vs_error_quick_prints_every_mode():
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks/time_vs_error.py"), "--quick", "--repeats", "1"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stderr
    rows = [line for line in run.stdout.splitlines() if line.startswith("| ")][1:]
    assert len(rows) == 7
    assert sum("adaptive" in row for row in rows) == 3

"""The benchmarks that need the compiled engine run and print their tables (the others:
tests/test_benchmarks.py). Here, numba's tests lane runs them (README's fast lane); without numba
this module is skipped (conftest.py).

Not here: compile_time's test (tests/test_benchmarks.py), which compiles every kernel from an
empty cache, minutes of a lane's time, and runs where numba is installed by hand."""

import subprocess
import sys

import numpy as np
from benchmark_runs import TIMEOUT, benchmark_module, table_rows

from conftest import REPO
from raykit.engine.choice import compiled_refuses
from raykit.io.scene_json import load_scene

_SCENES = {p.stem: load_scene(p) for p in sorted((REPO / "scenes").glob("*.json"))}
# the example scenes the compiled engine renders whose viewing rays the screen tiles serve
# (stage 5's distributed ones walk the tree)
PINHOLE_EXAMPLES = [
    name
    for name, scene in _SCENES.items()
    if compiled_refuses(scene) is None and not scene.distributed
]


def test_tile_sides_benchmark_marks_the_side_the_compiled_engine_chooses():
    rows = table_rows("engines.py", "--tile-sides")
    assert [row.split(" | ")[0][2:] for row in rows] == PINHOLE_EXAMPLES
    for row in rows:
        cells = row.strip("| ").split(" | ")[1:]
        assert len(cells) == 8 and all("ms" in cell for cell in cells)
        assert sum(cell.endswith("*") for cell in cells) == 1  # tile_side's choice, once


def test_a_render_child_renders_its_engines_scene_each_time_it_is_asked_and_says_how_long():
    """The child process each engine's renders are timed in (compile_time.py, parts 2 and 3)."""
    compile_time = benchmark_module("compile_time")
    children = {"now": compile_time.render_child("now", ["cutouts"], [None], None, True)}
    child, _, chosen = children["now"]
    try:
        took = [
            compile_time.timed_render(child, "cutouts", None, threads, clock)()
            for threads, clock in ((1, "wall"), (2, "wall"), (1, "cpu"))
        ]
    finally:
        compile_time.close(children)
    assert all(0 < seconds < 60 for seconds in took)
    assert list(chosen) == ["cutouts"] and chosen["cutouts"][0] in (4, 8, 16)
    assert child.returncode == 0


def test_engine_agreement_prints_each_kind_of_scene_and_saves_a_scene_that_loads(tmp_path):
    rows = table_rows(
        "engine_agreement.py", "--scenes", "3", "--out", str(tmp_path / "out"), repeats=False
    )
    assert rows and all(row.count(" | ") == 2 for row in rows)  # kind | scenes | mismatches
    assert all(row.strip("| ").split(" | ")[2] == "0" for row in rows)  # the engines agree
    assert not (tmp_path / "out").exists()  # no scene that disagrees saved
    save = benchmark_module("engine_agreement").save
    from random_scenes import make_textures, random_scene

    rng = np.random.default_rng(5)
    textures = make_textures(rng, tmp_path / "work" / "textures")
    data = random_scene(rng, textures)[0]
    data["billboards"] = [*data.get("billboards", []), {
        "upper_left": [0, 1, 0], "lower_left": [0, 0, 0], "upper_right": [1, 1, 0],
        "image": "textures/" + textures[0],
    }]  # fmt: skip
    saved = save(data, tmp_path / "out", "a_scene", tmp_path / "work")
    assert load_scene(saved).billboards[-1].texture.rgba.shape[:2] == (1, 1)


def test_thresholds_sets_a_compiled_constant_in_every_module_that_holds_it_before_compiling():
    code = """
import sys
sys.path.insert(0, {benchmarks!r})
import thresholds
thresholds.set_constants({{"raykit.engine.compiled.bvh.DIRECT_HITS": 0,
                          "raykit.engine.compiled.tiles.HOLDING_CHUNK": 3, "_nrt": True}})
from raykit.engine import compiled
from raykit.engine.compiled import bvh, compiling, jobs, shadows, tiles
render = sys.modules["raykit.engine.compiled.render"]  # the package's render is the function
assert bvh.DIRECT_HITS == render.DIRECT_HITS == compiled.DIRECT_HITS == 0
assert tiles.HOLDING_CHUNK == jobs.HOLDING_CHUNK == compiled.HOLDING_CHUNK == 3
assert shadows.shadow_lists.targetoptions["_nrt"] is True
assert "_nrt" not in render.cast_rays.targetoptions  # one that makes arrays: left alone
assert compiling.KERNEL["_nrt"] is thresholds.code_value(thresholds.CONSTANTS[-1])
"""
    run = subprocess.run(
        [sys.executable, "-c", code.format(benchmarks=str(REPO / "benchmarks"))],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert run.returncode == 0, run.stderr

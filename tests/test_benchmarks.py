"""The benchmarks run and print their tables (their figures are for people, not assertions)."""

import math
import subprocess
import sys
import types

import numpy as np
import pytest
from benchmark_runs import TIMEOUT, benchmark_module, table_rows, tables

from conftest import REPO
from raykit.engine.choice import compiled_refuses
from raykit.io.scene_json import load_scene


def test_render_speed_quick_prints_a_row_per_scene_with_every_variant():
    rows = table_rows("render_speed.py")
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
        timeout=TIMEOUT,
    )
    table = run.stdout.split("| scene | float64 | float32")[1].split("\n\n")[0]
    examples = len(list((REPO / "scenes").glob("*.json")))
    assert table.count(" of ") == 3 + examples  # the benchmark scenes and every example scene


def test_render_speed_whole_process_says_where_the_time_of_raykit_render_goes():
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks/render_speed.py"), "--whole-process"],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert run.returncode == 0, run.stderr
    assert "| scene |" not in run.stdout  # only the whole process's tables
    steps = run.stdout.split("spends its time | median |")[1].split("\n\n")[0]
    rows = [line for line in steps.splitlines() if line.startswith("| ")]
    assert [row.split(" | ")[0] for row in rows] == [
        "| Python starting (`python -c pass`)",
        "| importing numpy and Pillow",
        "| importing raykit's modules",
        "| loading the scene (JSON, textures)",
        "| rendering (numpy engine, first render in the process)",
        "| writing the PNG",
    ]
    assert all(row.endswith(" ms |") for row in rows)


def test_time_vs_error_quick_prints_every_mode():
    rows = table_rows("time_vs_error.py")
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
        timeout=TIMEOUT,
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.count("$ python benchmarks/") == 7
    assert "| mirror_balls |" in run.stdout and "| level 2 |" in run.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "engines.png",
        "forward_backward.png",
        "mitsuba_compare.png",
        "object_order.png",
        "shading_cost.png",
        "time_vs_error.png",
        "time_vs_objects.png",
    ]
    # a line on stderr as each script starts and ends, never inside the tables on stdout
    said = [line for line in run.stderr.splitlines() if line.startswith("raykit bench: ")]
    scripts = ["render_speed", "time_vs_error", "shading_cost", "mitsuba_compare"]
    scripts += ["object_order", "forward_backward", "engines"]
    assert [line.split()[3] for line in said] == [
        f"benchmarks/{name}.py{end}" for name in scripts for end in ("", ":")
    ]
    assert said[0] == "raykit bench: [1/7] benchmarks/render_speed.py ..."
    assert said[-1].startswith("raykit bench: [7/7] benchmarks/engines.py: done in ")
    assert "raykit bench" not in run.stdout


def test_mitsuba_comparison_times_raykit_and_mitsuba_when_installed():
    printed = [t for t in tables("mitsuba_compare.py") if t and t[0].startswith("| scene |")]
    flat, lit = ([line.split(" | ") for line in t[2:]] for t in printed)
    assert [row[0] for row in lit] == [row[0] + " lit" for row in flat]  # the same scenes, lit
    for rows in (flat, lit):
        renderers = [row[1] for row in rows]
        assert renderers.count("raykit numpy") == 2  # one row per quick scene
        try:
            import numba  # noqa: F401

            assert renderers.count("raykit compiled") == 2  # side by side, in the same run
        except ImportError:
            assert "raykit compiled" not in renderers
        try:
            import mitsuba  # noqa: F401
        except ImportError:
            continue  # an optional benchmark dependency: raykit alone is timed
        assert sum(r.startswith("Mitsuba") for r in renderers) == 4


def test_lit_scene_in_mitsuba_is_raykits_picture_once_its_fall_off_is_undone():
    mi = pytest.importorskip("mitsuba")
    sys.path.insert(0, str(REPO / "benchmarks"))
    from mitsuba_compare import agreement, check_pictures, lit, scene_data

    from raykit.io.scene_json import scene_from_dict
    from raykit.render import render

    mi.set_variant("scalar_rgb")
    camera = {"eye": [0, 2, 6], "lookat": [0, 0.5, 0], "up": [0, 1, 0], "fov_angle": 40}
    flat = scene_from_dict(
        {
            "camera": {**camera, "width": 48, "height": 36},
            "spheres": [
                {"center": [0, 0.6, 0], "radius": 0.6, "color": [0.8, 0.3, 0.2]},
                {"center": [1.2, 0.3, 0.8], "radius": 0.3, "color": [0.2, 0.5, 0.9]},
            ],
            "billboards": [  # its corners make its normal point down, away from the camera
                {
                    "upper_left": [-3, 0, -3],
                    "upper_right": [3, 0, -3],
                    "lower_left": [-3, 0, 3],
                    "color": [0.6, 0.6, 0.5],
                }
            ],
        }
    )
    scene = lit(flat, (([2, 4, 3], [0.7, 0.6, 0.5]), ([-3, 3, 1], [0.3, 0.3, 0.4])))
    image = render(scene, engine="numpy")
    pictures = check_pictures(scene_data(scene), mi)
    hits, mean, off, converted = agreement(
        scene, (image.rgb, image.object_index, image.t), pictures
    )
    assert hits == 1.0
    assert mean < 1e-4 and off == 0.0  # Mitsuba computes in float32
    assert converted[image.object_index >= 0].mean() > 0.05  # lit, not black on both sides
    unlit = check_pictures(scene_data(flat), mi)
    assert (unlit["lights"].shape[0], unlit["depth"].shape) == (0, (36, 48))  # no light: depth only


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
    rows = table_rows("object_order.py")
    assert [row.split(" | ")[0] for row in rows] == ["| 1", "| 10", "| 100"]
    assert all(row.count(" ms") + row.count(" s ") >= 3 for row in rows)


def test_forward_backward_quick_prints_both_directions():
    rows = table_rows("forward_backward.py")
    directions = [row.split(" | ")[0] for row in rows]
    assert directions == ["| backward"] * 2 + ["| forward"] * 2


def test_a_mitsuba_variant_that_cannot_start_is_a_failed_row_and_the_run_goes_on(
    monkeypatch, capsys
):
    # Mitsuba "installed" (a stand-in module here; the child imports the real one, or fails
    # to): a variant that cannot start gives each scene a one-line "failed: ..." row, and
    # every scene is still timed
    module = benchmark_module("mitsuba_compare")
    stand_in = types.ModuleType("mitsuba")
    stand_in.__version__ = "0.0"
    monkeypatch.setitem(sys.modules, "mitsuba", stand_in)
    monkeypatch.setattr(module, "VARIANTS", ("no_such_variant",))
    monkeypatch.setattr(
        sys, "argv", ["mitsuba_compare.py", "--quick", "--repeats", "1", "--engine", "numpy"]
    )
    module.main()
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| ")]
    failed = [row for row in rows if "Mitsuba 0.0 no_such_variant" in row]
    assert len(failed) == 4  # one per quick scene, flat and lit
    assert all(row.split(" | ")[2].startswith("failed: ") for row in failed)
    assert sum(" | raykit numpy | " in row for row in rows) == 4


def test_the_mitsuba_summary_puts_each_thread_counts_ratios_side_by_side(capsys):
    module = benchmark_module("mitsuba_compare")
    rows = []
    for threads, ratio in ((1, "0.40"), (2, "0.45")):
        rows += [
            {"scene": "classic", "renderer": f"raykit compiled, {threads} t", "cpu": "native",
             "threads": threads, "ratio": ratio, "whole_ratio": "0.30", "cold_ratio": None},
            {"scene": "textured", "renderer": f"raykit compiled, {threads} t", "cpu": "native",
             "threads": threads, "ratio": "0.20", "whole_ratio": "0.25", "cold_ratio": "0.55"},
            {"scene": "classic", "renderer": f"Mitsuba 3.9 llvm_ad_rgb, {threads} threads",
             "cpu": "native", "threads": threads, "render": 0.1},
        ]  # fmt: skip
    module.summary(rows)
    table = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| ")]
    assert table == [
        "| scene | instruction set | 1 thread: render | load + prepare + render |"
        " 2 threads: render | load + prepare + render |",
        "| classic | native | 0.40 | 0.30 | 0.45 | 0.30 |",
        "| textured | native | 0.20 | 0.25 (textures not cached: 0.55) | 0.20 |"
        " 0.25 (textures not cached: 0.55) |",
    ]


def test_a_mitsuba_childs_run_time_is_read_and_settle_returns_for_a_still_or_gone_child():
    # settle() waits while the child's threads run (Dr.Jit's pool after a render); here a
    # stand-in child computes, then sleeps: its run time grows, and a sleeping or gone child
    # is still
    module = benchmark_module("mitsuba_compare")
    child = object.__new__(module.MitsubaChild)
    code = "\n".join(
        ["import time", "print(0, flush=True)", "input()", "sum(range(3_000_000))",
         "print(1, flush=True)", "time.sleep(60)"]
    )  # fmt: skip
    child.process = subprocess.Popen(
        [sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE
    )
    try:
        assert child.process.stdout.readline() == b"0\n"  # started, waiting
        first = child._ran()
        if first is None:
            pytest.skip("no /proc/PID/task/*/schedstat here")
        child.process.stdin.write(b"go\n")
        child.process.stdin.flush()
        assert child.process.stdout.readline() == b"1\n"  # done computing
        assert child._ran() > first
        child.settle()  # asleep: still
        assert child._ran() == child._ran()
    finally:
        child.process.kill()
        child.process.wait()
        child.process.stdout.close()
        child.process.stdin.close()
    assert child._ran() is None
    child.settle()  # gone: returns at once


def test_a_mitsuba_child_that_dies_during_the_renders_is_a_failure_not_a_crash():
    pytest.importorskip("mitsuba")
    module = benchmark_module("mitsuba_compare")
    data = module.scene_data(module.benchmark_scenes(True)["sphereflake 2 128x128"])
    child = module.MitsubaChild("scalar_rgb", data)
    assert child.failure is None and child.render_once() > 0
    child.process.kill()
    assert math.isnan(child.render_once())
    assert child.failure.startswith("failed: ") and "\n" not in child.failure
    assert math.isnan(child.render_once())  # and it stays failed, without asking again
    child.close()


def test_turns_give_each_timer_its_own_median_and_warm_it_first():
    module = benchmark_module("common")
    calls = []

    def timer(key, seconds):
        def timed():
            calls.append(key)
            return seconds.pop(0)

        return timed

    medians = module.medians_in_turns(
        {"a": timer("a", [9, 1, 9, 2, 9, 3]), "b": timer("b", [9, 5, 9, 6, 9, 4])}, 3, warm=True
    )
    assert medians == {"a": 2, "b": 5}  # the untimed warm-up calls (9) are left out
    assert calls == ["a", "a", "b", "b", "b", "b", "a", "a", "a", "a", "b", "b"]  # reversed


def _panels(figure) -> dict:
    """A bar plot's (common.bar_plot) panels, by title: each bar's height by its label."""
    return {
        ax.get_title(): {c.get_label(): round(c[0].get_height(), 6) for c in ax.containers}
        for ax in figure.axes
        if ax.get_visible()
    }


def test_mitsuba_plot_draws_a_bar_per_scene_and_renderer(tmp_path, monkeypatch):
    # Mitsuba is not installed here: made-up rows exercise the plot, a failed variant included
    import matplotlib.pyplot as plt

    module = benchmark_module("mitsuba_compare")
    rows = [
        {"scene": "classic", "renderer": "raykit", "render": 0.081},
        {"scene": "classic", "renderer": "Mitsuba 3.6 scalar_rgb", "render": 0.4},
        {"scene": "classic", "renderer": "Mitsuba 3.6 llvm_ad_rgb", "render": 0.018},
        {"scene": "sphereflake 4", "renderer": "raykit", "render": 0.152},
        {"scene": "sphereflake 4", "renderer": "Mitsuba 3.6 scalar_rgb", "render": 0.9},
        {"scene": "sphereflake 4", "renderer": "Mitsuba 3.6 llvm_ad_rgb", "render": None},
    ]
    drawn = {}
    monkeypatch.setattr(plt, "close", lambda figure: drawn.setdefault("figure", figure))
    module.plot(tmp_path / "mitsuba.png", rows)
    assert _panels(drawn["figure"]) == {
        "classic": {"raykit": 81, "Mitsuba 3.6 scalar_rgb": 400, "Mitsuba 3.6 llvm_ad_rgb": 18},
        "sphereflake 4": {"raykit": 152, "Mitsuba 3.6 scalar_rgb": 900},  # a failed variant: none
    }  # milliseconds
    shown = [ax for ax in drawn["figure"].axes if ax.get_visible()]
    assert {ax.get_yscale() for ax in shown} == {"log"}  # ms to s: a linear scale hides the fast
    legend = drawn["figure"].legends[0]
    assert [t.get_text() for t in legend.get_texts()] == [
        "raykit",
        "Mitsuba 3.6 scalar_rgb",
        "Mitsuba 3.6 llvm_ad_rgb",
    ]
    assert (tmp_path / "mitsuba.png").stat().st_size > 1000
    plt.close("all")


def test_shading_cost_plot_draws_flat_shaded_and_unculled_per_scene(tmp_path, monkeypatch):
    import matplotlib.pyplot as plt

    module = benchmark_module("shading_cost")
    rows = [
        {"scene": "classic", "image": "640x480", "flat": 0.08, "shaded": 0.08, "unculled": 0.076},
        {"scene": "mirror_balls", "image": "640x480", "flat": 0.067, "shaded": 0.35}
        | {"unculled": 0.34},
    ]
    drawn = {}
    monkeypatch.setattr(plt, "close", lambda figure: drawn.setdefault("figure", figure))
    module.plot(tmp_path / "shading.png", rows)
    assert _panels(drawn["figure"]) == {
        "classic": {"flat (v1)": 80, "shaded": 80, "shaded, no culling": 76},
        "mirror_balls": {"flat (v1)": 67, "shaded": 350, "shaded, no culling": 340},
    }
    assert (tmp_path / "shading.png").stat().st_size > 1000
    plt.close("all")


def test_a_bar_plot_panel_title_breaks_a_long_scene_name_after_an_underscore(tmp_path, monkeypatch):
    import matplotlib.pyplot as plt

    common = benchmark_module("common")
    drawn = {}
    monkeypatch.setattr(plt, "close", lambda figure: drawn.setdefault("figure", figure))
    common.bar_plot(tmp_path / "bars.png", ["shadow_on_billboard_far_away"], {"a": [0.002]}, "ms")
    assert list(_panels(drawn["figure"])) == ["shadow_on_\nbillboard_far_\naway"]
    plt.close("all")


_SCENES = {p.stem: load_scene(p) for p in sorted((REPO / "scenes").glob("*.json"))}
# the example scenes the compiled engine renders (every one, motion blur included)
EXAMPLES = [name for name, scene in _SCENES.items() if compiled_refuses(scene) is None]


def test_engines_benchmark_times_both_engines_on_every_example_scene():
    rows = table_rows("engines.py")
    assert [row.split(" | ")[0][2:] for row in rows] == EXAMPLES
    try:
        import numba  # noqa: F401
    except ImportError:  # the numpy engine alone: no compiled column filled
        assert all(row.split(" | ")[4] == "not run" for row in rows)
        return
    assert all(row.split(" | ")[4].endswith("ms") for row in rows)  # a compiled time each


def test_compile_time_times_each_entry_points_first_use_from_an_empty_cache():
    pytest.importorskip("numba")
    rows = table_rows("compile_time.py")
    entries = [("classic", "trace_flat"), ("classic_lit", "trace_lit"),
               ("mirror_balls", "trace_mirrors"), ("soft_shadows", "trace_sampled"),
               ("glossy", "trace_sampled_mirrors"), ("motion_blur", "trace_moving")]  # fmt: skip
    assert [row.split(" | ")[:3] for row in rows] == [
        [f"| {name}", entry, when] for name, entry in entries for when in ("empty", "cached")
    ]
    assert all(row.endswith(" MB |") for row in rows)  # each with its peak memory


def test_the_large_textures_bench_scene_is_classic_with_each_texture_256_square_rgba(tmp_path):
    from raykit.io.scene_json import load_scene

    scenes = benchmark_module("scenes")
    scene = load_scene(scenes.classic_with_large_textures(tmp_path))
    classic = load_scene(REPO / "scenes/classic.json")
    assert len(scene.spheres) == len(classic.spheres) and len(scene.billboards) == 4
    for board, original in zip(scene.billboards, classic.billboards, strict=True):
        assert board.texture.rgba.shape == (256, 256, 4)
        assert np.array_equal(board.upper_left, original.upper_left)
    again = load_scene(scenes.classic_with_large_textures(tmp_path / "again"))  # seeded
    assert all(
        np.array_equal(a.texture.rgba, b.texture.rgba)
        for a, b in zip(scene.billboards, again.billboards, strict=True)
    )


def test_sampling_error_quick_prints_each_effect_every_sampler_and_their_slopes(tmp_path):
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks/sampling_error.py"), "--quick", "--repeats", "1"]
        + ["--cache", str(tmp_path / "cache"), "--plot", str(tmp_path / "error.png")],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert run.returncode == 0, run.stderr
    effects = ["antialiasing", "soft shadows", "depth of field", "glossy reflection", "motion blur"]
    raykit_rows = [f"| raykit | {sampler}" for sampler in ("random", "jittered", "sobol")]
    for effect in effects:
        table = run.stdout.split(f"## {effect}\n")[1].split("\n\n")[1].splitlines()
        assert table[0] == "| renderer | sampler | 1 spp | 4 spp | 16 spp |"
        assert [" | ".join(row.split(" | ")[:2]) for row in table[2:]] == raykit_rows
        assert all(row.count(", ") == 3 for row in table[2:])  # an error and a time per count
    slopes = run.stdout.split("| effect | sampler | measured slope | theory |")[1]
    rows = [row.split(" | ") for row in slopes.split("\n\n")[0].splitlines()[2:]]
    assert len(rows) == 3 * len(effects)
    assert all(-2.0 < float(row[2]) < 0.0 for row in rows)  # error falls as samples grow
    assert "Mitsuba" not in run.stdout.split("\n\n", 1)[1]  # the race is race.py's
    assert (tmp_path / "error.png").stat().st_size > 1000
    assert len(list((tmp_path / "cache").glob("*.npy"))) == len(effects)  # a reference each


def test_race_reads_times_to_error_off_log_log_curves():
    module = benchmark_module("race")
    spp = [1, 4, 16, 64]
    steep = module.Curve("raykit", "jittered", 1, spp, {n: [n**-1.5] for n in spp})
    steep.seconds, steep.load = {n: 0.01 * n for n in spp}, 0.5  # time proportional to samples
    # between 4 and 16 spp, error 4^-0.75 .. 16^-0.75: the level halfway in log is 8 spp's
    assert module.time_to(steep, 8**-0.75) == (pytest.approx(0.08), False)
    with_load = module.time_to(steep, 8**-0.75, load=True)[0]  # halfway in log between 0.54, 0.66
    assert with_load == pytest.approx((0.54 * 0.66) ** 0.5)
    assert module.time_to(steep, 2.0) == (0.01, True)  # reached at 1 spp already: its time
    assert module.time_to(steep, 1e-6) is None  # below the last: never extrapolated
    flat = module.Curve("Mitsuba", "independent", 1, spp, {n: [0.25**2] for n in spp})
    flat.seconds = {n: 0.002 * n for n in spp}
    assert module.fastest([steep, flat], "Mitsuba", 0.3, False) == 0.002
    assert module.fastest([steep, flat], "Mitsuba", 0.1, False) is None


def test_race_prints_no_ratio_at_a_level_below_the_references_noise(capsys):
    module = benchmark_module("race")
    spp = [1, 4, 16, 64]
    curves = []
    for renderer, seconds in (("raykit", 0.01), ("Mitsuba", 0.02)):
        curve = module.Curve(renderer, "jittered", 1, spp, {n: [n**-3.0] for n in spp})
        curve.seconds = {n: seconds * n for n in spp}  # RMS error n^-1.5: 0.002 at 64 spp
        curves.append(curve)
    measured = module.print_times(curves, [1], floor=0.0)
    capsys.readouterr()
    above_noise = module.print_times(curves, [1], floor=0.004)
    rows = {row.split(" | ")[0]: row for row in capsys.readouterr().out.splitlines()}
    assert len(measured) == 6 and all(r == pytest.approx(0.5) for r in measured)
    assert len(above_noise) == 4  # 0.003 and 0.002 lie below the noise
    assert rows["| 0.003"].endswith("| - | - |") and rows["| 0.005"].endswith("| 0.50 | 0.50 |")


def test_race_without_mitsuba_says_so_and_races_nothing(tmp_path):
    try:
        import mitsuba  # noqa: F401

        pytest.skip("Mitsuba is installed: the race runs (benchmarks/race.py)")
    except ImportError:
        pass
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks/race.py"), "--quick", "--repeats", "1",
         "--cache", str(tmp_path)],
        capture_output=True, text=True, timeout=TIMEOUT,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert "Mitsuba 3 is not installed (pip install mitsuba): nothing to race." in run.stdout


def test_race_converts_each_effect_to_the_same_picture_in_mitsuba():
    """Each raced effect in Mitsuba: the physically based panel as a rectangle emitter of its
    radiance lighting the side a × b points to, the flat scenes' objects as emitters of their
    colours; the converged pictures are compared by race.py itself."""
    mi = pytest.importorskip("mitsuba")
    module = benchmark_module("race")
    mi.set_variant("scalar_rgb")
    made = {effect.name: effect for effect in module.effects(32, 24)}
    assert list(made) == ["antialiasing", "soft shadows", "depth of field"]
    soft = made["soft shadows"].data
    (light,) = soft["lights"]
    assert "radiance" in light and "color" not in light and "ambient" not in soft
    assert module.scene_from_dict(soft).lights[0].physical
    converted = module.mitsuba_scene(soft, mi, "stratified")
    emitter = converted["light0"]
    normal = np.array(emitter["to_world"] @ mi.ScalarNormal3f(0, 0, 1))
    assert normal[1] < 0  # a × b of the panel points down, to the scene
    assert emitter["emitter"]["radiance"]["value"] == light["radiance"]
    flat = module.mitsuba_scene(made["antialiasing"].data, mi, "independent")
    assert flat["integrator"] == {"type": "path", "max_depth": 1}
    assert all("emitter" in flat[f"sphere{i}"] for i in range(10))


def test_mitsuba_compare_turns_an_area_light_to_face_the_scene_or_keeps_a_physical_ones_side():
    mi = pytest.importorskip("mitsuba")
    from mitsuba_compare import mitsuba_light

    mi.set_variant("scalar_rgb")
    # corner and edges whose cross product points up, away from the scene below it
    light = {"type": "area", "corner": [-1.0, 4, 0.5], "edge1": [2.0, 0, 0],
             "edge2": [0.0, 0, -1], "color": [0.8, 0.6, 0.4]}  # fmt: skip
    camera = {"eye": [0, 2, 8], "lookat": [0, 0, 0], "up": [0, 1, 0], "fov_angle": 40}
    made = mitsuba_light(light, camera, mi)
    normal = np.array(made["to_world"] @ mi.ScalarNormal3f(0, 0, 1))
    assert normal[1] < 0  # FOCG's light, two-sided: flipped to light the lookat point's side
    # at lookat, 4.0 below the light's centre and straight under it, Mitsuba's (kd/π)·L·A/r²
    # is raykit's kd·I: L = π·I·r²/A
    radiance = np.array(made["emitter"]["radiance"]["value"])
    np.testing.assert_allclose(radiance, np.pi * np.array(light["color"]) * 4.0**2 / 2.0)
    physical = {key: value for key, value in light.items() if key != "color"}
    physical["radiance"] = [3.0, 2.0, 1.0]
    made = mitsuba_light(physical, camera, mi)  # one-sided: the side a × b points to, as raykit's
    assert np.array(made["to_world"] @ mi.ScalarNormal3f(0, 0, 1))[1] > 0
    assert made["emitter"]["radiance"]["value"] == [3.0, 2.0, 1.0]


NUMPY_CONSTANTS = ["BVH_FROM", "TILE", "CROWDED", "POINTS_PER_CALL"]


@pytest.mark.slow
def test_thresholds_prints_each_constant_with_the_code_value_and_times_the_numpy_engines():
    """The compiled engine's constants compile a child per value (minutes): --only leaves them
    out, and the summary still names each with its value in the code."""
    thresholds = benchmark_module("thresholds")
    printed = tables("thresholds.py", "--only", ",".join(NUMPY_CONSTANTS))
    summary = next(t for t in printed if t[0] == "| constant | module | in the code | measured | |")
    rows = [row.strip("| ").split(" | ") for row in summary[2:]]
    assert [row[0] for row in rows] == [c.name for c in thresholds.CONSTANTS]
    for row, constant in zip(rows, thresholds.CONSTANTS, strict=True):
        assert row[2] == str(thresholds.code_value(constant))
        if constant.name in NUMPY_CONSTANTS:
            assert row[3] != "not run" and row[4].startswith(("agrees", "disagrees"))
        else:
            assert row[3] == "not run"
    for constant in thresholds.CONSTANTS[: len(NUMPY_CONSTANTS)]:  # the code's choice, once a row
        heading = printed.index([f"## {constant.name} ({constant.module})"])
        rows = [row for row in printed[heading + 2][2:] if not row.startswith("| time / ")]
        assert rows and all(row.count("*") == 1 for row in rows)

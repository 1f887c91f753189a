"""The numpy engine against the compiled one (raykit[fast]), and what engine="auto" chooses.

    python benchmarks/engines.py [--quick] [--repeats N] [--plot engines.png]

1. Render medians of both engines, side by side in this process (kernels loaded first), on
   every example scene and on the benchmark scenes; each lit scene also as a ratio to the
   compiled flat classic render. The numpy engine's time per ray, flat and lit, is what
   raykit.engine.choice.NUMPY_SECONDS_PER_RAY estimates.
2. What the compiled engine costs a process before it renders: importing numba and loading
   the cached kernels (whole processes rendering a tiny lit scene with 3 x 3 adaptive samples,
   and a tiny distributed one, median, compiled and numpy in turns), and one first compile into
   an empty cache.
   With 1., that gives the numpy render time from which the compiled engine wins, the
   threshold raykit.engine.choice.AUTO_FROM holds.
3. Whole processes, `raykit render SCENE -o OUT.png --engine E` for numpy, compiled and auto,
   taken in turns: auto against the better of the other two.

With ``--tile-sides``, instead: the compiled engine's render of each prepared scene (sphereflakes
5 and 6 too) with tiles of 2 to 16 pixels a side whose rays go one at a time, and of 4 to 32
whose rays go in packets, and the choice raykit.engine.compiled.tile_side makes.

Needs numba (`pip install -e ".[fast]"`); without it, says so and times the numpy engine only.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import (  # noqa: E402
    arguments,
    bar_plot,
    interleaved_medians,
    parse,
    seconds,
)

from raykit.engine import choice  # noqa: E402
from raykit.io.scene_json import load_scene  # noqa: E402
from raykit.render import render  # noqa: E402
from raykit.shading import needs_shading  # noqa: E402
from scenes import many_spheres, sphereflake  # noqa: E402

SCENES = HERE.parent / "scenes"


def benchmark_scenes(quick: bool, *, format_v1_only: bool = False) -> dict:
    """The example scenes (with ``format_v1_only``, those of scene format v1, which every
    revision of raykit reads: compile_time.py's ``--before`` renders them with an older one),
    and, unless ``quick``, the generated benchmark scenes."""
    files = sorted(SCENES.glob("*.json"))
    if format_v1_only:
        files = [p for p in files if json.loads(p.read_text()).get("version", 1) == 1]
    scenes = {p.stem: load_scene(p) for p in files}
    if not format_v1_only:  # (a v1 scene renders in every engine; an older raykit has no
        # choice.compiled_refuses)
        # what the compiled engine does not render yet (nothing of stage 5): nothing to compare
        scenes = {name: s for name, s in scenes.items() if choice.compiled_refuses(s) is None}
    if not quick:
        scenes["sphereflake 4"] = sphereflake(4)
        scenes["1,000 spheres 1080p"] = many_spheres(1000)
    return scenes


def _processes(variants: dict[str, list[str]], repeats: int, **env) -> dict[str, float]:
    """The median wall time of each variant's Python process (key: its arguments), the variants
    taken in turns (:func:`common.interleaved_medians`): whole processes vary the most, and a
    burst of load must fall on all of them alike for their ratios to mean anything."""

    def process(arguments: list[str]):
        return lambda: subprocess.run(
            [sys.executable, *arguments],
            check=True,
            capture_output=True,
            env={**os.environ, **env},
        )

    return interleaved_medians(
        {key: process(arguments) for key, arguments in variants.items()}, repeats
    )


def main() -> None:
    parser = arguments(__doc__, "the example scenes only, fewer whole processes", repeats=5)
    parser.add_argument("--plot", type=Path, help="write the render medians as bars here")
    parser.add_argument(
        "--tile-sides", action="store_true", help="time the compiled engine's tile sides instead"
    )
    args = parse(parser)
    if args.tile_sides:
        return tile_sides(args)
    engines = ["numpy", "compiled"] if choice.compiled_available() else ["numpy"]
    if len(engines) == 1:
        print('numba is not installed (pip install -e ".[fast]"): the numpy engine alone.\n')
    scenes = benchmark_scenes(args.quick)

    print("1. render medians in one process, kernels loaded first, each engine's scenes in turns\n")
    print(
        "| scene | pixels | lit | numpy | compiled | numpy / compiled | / compiled flat classic |"
    )
    print("|---|---|---|---|---|---|---|")
    times: dict[str, dict[str, float]] = {name: {} for name in scenes}
    for engine in engines:  # one engine at a time (the other's renders would cool its caches)
        calls = {
            name: lambda s=scene, e=engine: render(s, engine=e) for name, scene in scenes.items()
        }
        for call in calls.values():
            call()  # warm-up: loads (or compiles) the kernels
        for name, took in interleaved_medians(calls, args.repeats).items():
            times[name][engine] = took
    per_ray = {"flat": [], "lit": [], "distributed": []}
    for name, scene in scenes.items():
        pixels = scene.camera.width * scene.camera.height
        lit = needs_shading(scene)
        kind, rays = "lit" if lit else "flat", pixels
        if scene.distributed:  # per sample ray (choice.numpy_seconds counts them so)
            kind, rays = "distributed", pixels * scene.sampling.samples_per_pixel
        per_ray[kind].append(times[name]["numpy"] / rays)
        fast = times[name].get("compiled")
        classic = times.get("classic", {}).get("compiled")
        ratio = f"{times[name]['numpy'] / fast:.1f}x" if fast else "-"
        to_classic = f"{fast / classic:.1f}x" if fast and classic and lit else "-"
        print(
            f"| {name} | {pixels:,} | {'yes' if lit else 'no'} "
            f"| {seconds(times[name]['numpy'], 1)} | {seconds(fast, 1)} | {ratio} | {to_classic} |"
        )
    flat, lit, distributed = (statistics.median(per_ray[k]) for k in ("flat", "lit", "distributed"))
    print(
        f"\nThe numpy engine per pixel, median over the scenes: {flat * 1e9:.0f} ns flat, "
        f"{lit * 1e9:.0f} ns lit, and per sample ray of a distributed scene "
        f"{distributed * 1e9:.0f} ns (raykit.engine.choice.NUMPY_SECONDS_PER_RAY: "
        f"{choice.NUMPY_SECONDS_PER_RAY['flat'] * 1e9:.0f}, "
        f"{choice.NUMPY_SECONDS_PER_RAY['lit'] * 1e9:.0f} and "
        f"{choice.NUMPY_SECONDS_PER_RAY['distributed'] * 1e9:.0f} ns)."
    )
    if len(engines) == 1:
        return _plot(args.plot, times, engines)

    print("\n2. what the compiled engine costs a process before it renders (whole processes)\n")
    tiny, tiny_distributed = _tiny("classic_lit", "3, adaptive=True, "), _tiny("soft_shadows", "")
    tiny_processes = _processes(
        {
            (code, engine): ["-c", code.format(engine)]
            for code in (tiny, tiny_distributed)
            for engine in ("numpy", "compiled")
        },
        args.repeats,
    )
    base, load = tiny_processes[tiny, "numpy"], tiny_processes[tiny, "compiled"]
    compile_time = "not run (--quick)"
    if not args.quick:
        with tempfile.TemporaryDirectory() as empty:
            first = ["-c", tiny.format("compiled")]
            took = _processes({"first": first}, 1, RAYKIT_CACHE_DIR=empty)["first"]
            compile_time = f"{took:.1f} s"
    overhead = load - base
    print("| a tiny render, numpy | compiled: + numba and the cached kernels | first compile |")
    print("|---|---|---|")
    print(f"| {seconds(base, 0)} | +{seconds(overhead, 0)} | {compile_time} |")
    saved = statistics.median(
        (t["numpy"] - t["compiled"]) / t["numpy"] for t in times.values() if t["numpy"] > 0
    )
    threshold = overhead / saved
    print(
        f"\nThe compiled engine saves a median {saved:.0%} of the numpy render time, so it wins "
        f"from numpy renders of about {overhead:.2f} / {saved:.2f} = {threshold:.2f} s "
        f"(raykit.engine.choice.AUTO_FROM: {choice.AUTO_FROM} s)."
    )
    distributed = [name for name, scene in scenes.items() if scene.distributed]
    overhead = (
        tiny_processes[tiny_distributed, "compiled"] - tiny_processes[tiny_distributed, "numpy"]
    )
    saved = statistics.median(
        (times[name]["numpy"] - times[name]["compiled"]) / times[name]["numpy"]
        for name in distributed
    )
    print(
        f"For a distributed scene ({', '.join(distributed)}; the tiny render soft_shadows at "
        f"8x6, whose kernels, trace_sampled's, load +{seconds(overhead, 0)}), it saves a median "
        f"{saved:.0%}, and wins from numpy renders of about {overhead:.2f} / {saved:.2f} = "
        f"{overhead / saved:.2f} s."
    )

    print(
        "\n3. whole processes: raykit render SCENE -o OUT.png --engine E "
        "(median, the three in turns)\n"
    )
    print("| scene | numpy | compiled | auto | auto chose | auto / the better |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for name, scene in scenes.items():
            path = _scene_file(name, scene, Path(folder))
            out = str(Path(folder) / "out.png")
            whole = _processes(
                {
                    engine: ["-m", "raykit", "render", str(path), "-o", out, "--engine", engine]
                    for engine in ("numpy", "compiled", "auto")
                },
                args.repeats,
            )
            chose = choice.choose("auto", load_scene(path))
            better = min(whole["numpy"], whole["compiled"])
            print(
                f"| {name} | {seconds(whole['numpy'], 0)} | {seconds(whole['compiled'], 0)} "
                f"| {seconds(whole['auto'], 0)} | {chose} | {whole['auto'] / better:.2f} |"
            )
    _plot(args.plot, times, engines)


def _tiny(name: str, options: str) -> str:
    """A process's code that renders the example scene ``name`` at 8x6 pixels with ``options``
    and the engine formatted in: a render too small to time, so that what is left is the
    process and the engine's loading."""
    return (
        "import dataclasses, raykit.io.scene_json as j, raykit.render as r\n"
        f"s = j.load_scene({str(SCENES / f'{name}.json')!r})\n"
        "s = dataclasses.replace(s, camera=dataclasses.replace(s.camera, width=8, height=6))\n"
        f"r.render(s, {options}engine={{!r}})\n"
    )


def tile_sides(args) -> None:
    """The compiled render of each prepared scene per tile side (see the module page)."""
    if not choice.compiled_available():
        print('numba is not installed (pip install -e ".[fast]"): nothing to time.')
        return
    from raykit.engine import compiled

    # a distributed render's rays walk the tree, never the screen tiles
    scenes = {name: s for name, s in benchmark_scenes(args.quick).items() if not s.distributed}
    if not args.quick:
        scenes |= {"sphereflake 5": sphereflake(5), "sphereflake 6": sphereflake(6)}
    choices = [(side, False) for side in (2, 4, 8, 16)] + [(side, True) for side in (4, 8, 16, 32)]
    print("compiled render of the prepared scene, median; * marks tile_side's choice\n")
    print(
        "| scene | "
        + " | ".join(f"{side} px{', packets' if packets else ''}" for side, packets in choices)
        + " |"
    )
    print("|---|" + "---|" * len(choices))
    for name, scene in scenes.items():
        prepared = compiled.prepare(scene)
        chosen = (prepared.tiles.size, prepared.tiles.packets)
        with_tiles = {
            layout: prepared._replace(tiles=compiled.screen_tiles(scene, prepared.arrays, *layout))
            for layout in choices
        }
        for each in with_tiles.values():
            compiled.render.render(each)  # warm-up
        # in turns, so that a burst of load from the machine's neighbours falls on every choice
        took = interleaved_medians(
            {
                layout: (lambda p=each: compiled.render.render(p))
                for layout, each in with_tiles.items()
            },
            args.repeats,
        )
        cells = [seconds(took[layout], 1) + ("*" if layout == chosen else "") for layout in choices]
        print(f"| {name} | " + " | ".join(cells) + " |")


def _scene_file(name: str, scene, folder: Path) -> Path:
    """An example scene's own file, or the benchmark scene written as JSON."""
    if (SCENES / f"{name}.json").exists():
        return SCENES / f"{name}.json"
    from mitsuba_compare import scene_data

    path = folder / f"{len(list(folder.glob('*.json')))}.json"
    path.write_text(json.dumps(scene_data(scene)))
    return path


def _plot(path: Path | None, times: dict, engines: list[str]) -> None:
    if path:
        names = list(times)
        bar_plot(
            path,
            names,
            {engine: [times[n][engine] for n in names] for engine in engines},
            "render time, median (ms, log scale)",
            "raykit's numpy and compiled engines, 1 sample per pixel",
            log=True,  # the two engines' times lie a decade or more apart
        )


if __name__ == "__main__":
    main()

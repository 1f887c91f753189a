"""raykit against Mitsuba 3 on the same scenes, in one run: load and render times, 1 sample
per pixel, pure ray casting.

    python benchmarks/mitsuba_compare.py [--quick] [--repeats N] [--plot mitsuba_compare.png]

Mitsuba is an optional benchmark dependency, never a runtime one (``pip install mitsuba``).
Its ``llvm_ad_rgb`` variant needs an LLVM it can load: on Debian 12, ``apt install libllvm19``
and ``DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1`` (Debian's default LLVM
15 makes it abort). Each Mitsuba variant runs in a child process of its own, so a variant that
aborts is reported as such and the run goes on.

The scenes are raykit's, converted: spheres to Mitsuba spheres; billboards to rectangles whose
``to_world`` maps [-1, 1]² onto the parallelogram; the camera to a ``perspective`` sensor with
the same eye, lookat, up and vertical fov. Mitsuba renders with its ``depth`` integrator (the
distance to the nearest hit: the same ray casting as raykit's object image, without texture
lookups); raykit renders its flat colours, textures included. Mitsuba's sampler jitters each
pixel's one sample, raykit takes the pixel centre, so their hit masks differ at silhouettes:
the table gives the share of pixels on which both agree whether anything is hit.

Load: raykit from its JSON data (validation included), Mitsuba ``load_dict`` (which builds
its BVH). Prepare, raykit's compiled engine only: ``raykit.engine.compiled.prepare``, the
scene's arrays, screen tiles and (lit scenes) BVH, made once per scene; its render renders the
prepared scene, as Mitsuba's renders its loaded one (``raykit.render.render`` does both). Render:
the median of ``--repeats`` renders after one warm-up render (for ``llvm_ad_rgb`` the warm-up
compiles its kernels; that first render is shown too). The last line checks the growth goals:
sphereflake 4 to 6 in at most 3x the render time, level 6 loaded, prepared and rendered in 2 s.
The growth ratio is timed anew, the two prepared sphereflakes rendered in turns (each timed
render after an untimed one of the same scene, so that its data are in the caches), since each
scene's median above is taken at its own time, and this machine's neighbours make those vary.
``--plot`` draws the render medians as bars per scene, one per renderer (raykit's alone when
Mitsuba is not installed).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import (  # noqa: E402
    arguments,
    bar_plot,
    interleaved_medians,
    median_time,
    parse,
    seconds,
)

from raykit.engine.choice import ENGINES  # noqa: E402
from raykit.io.scene_json import load_scene, scene_from_dict  # noqa: E402
from raykit.render import render  # noqa: E402
from raykit.scene import Scene  # noqa: E402
from scenes import many_spheres, sphereflake  # noqa: E402

VARIANTS = ("scalar_rgb", "llvm_ad_rgb")
LLVM_19 = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"


def benchmark_scenes(quick: bool) -> dict[str, Scene]:
    if quick:
        return {
            "classic 160x120": _sized(load_scene(HERE.parent / "scenes/classic.json"), 160, 120),
            "sphereflake 2 128x128": sphereflake(2, 128, 128),
        }
    return {
        "classic 640x480": load_scene(HERE.parent / "scenes/classic.json"),
        "sphereflake 4 512x512": sphereflake(4),
        "1,000 spheres 1920x1080": many_spheres(1000),
        "sphereflake 6 512x512": sphereflake(6),
    }


def _sized(scene: Scene, width: int, height: int) -> Scene:
    from dataclasses import replace

    return replace(scene, camera=replace(scene.camera, width=width, height=height))


def scene_data(scene: Scene) -> dict:
    """The scene as plain data: raykit's JSON fields (flat colours; textures as their
    paths), enough to rebuild it with ``scene_from_dict`` and to convert it for Mitsuba."""
    camera = scene.camera
    return {
        "camera": {
            "eye": list(map(float, camera.eye)),
            "lookat": list(map(float, camera.lookat)),
            "up": list(map(float, camera.up)),
            "fov_angle": camera.fov_angle,
            "width": camera.width,
            "height": camera.height,
        },
        "background": list(map(float, scene.background)),
        "spheres": [
            {
                "center": list(map(float, s.center)),
                "radius": float(s.radius),
                "color": list(map(float, s.color)),
            }
            for s in scene.spheres
        ],
        "billboards": [
            {
                "upper_left": list(map(float, b.upper_left)),
                "lower_left": list(map(float, b.lower_left)),
                "upper_right": list(map(float, b.upper_right)),
                **(
                    {"image": str(b.texture.path)}
                    if b.texture
                    else {"color": list(map(float, b.color))}
                ),
            }
            for b in scene.billboards
        ],
    }


def mitsuba_dict(data: dict, mi) -> dict:
    """Mitsuba's scene description of raykit scene data (see the module page)."""
    camera = data["camera"]
    scene = {
        "type": "scene",
        "integrator": {"type": "depth"},
        "sensor": {
            "type": "perspective",
            "fov": camera["fov_angle"],
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=camera["eye"], target=camera["lookat"], up=camera["up"]
            ),
            "film": {
                "type": "hdrfilm",
                "width": camera["width"],
                "height": camera["height"],
                "rfilter": {"type": "box"},
            },
            "sampler": {"type": "independent", "sample_count": 1},
        },
    }
    for i, s in enumerate(data["spheres"]):
        scene[f"sphere{i}"] = {"type": "sphere", "center": s["center"], "radius": s["radius"]}
    for i, b in enumerate(data["billboards"]):
        ul, ll, ur = (np.array(b[k]) for k in ("upper_left", "lower_left", "upper_right"))
        a, bb = ur - ul, ll - ul
        n = np.cross(a, bb)
        matrix = np.eye(4)
        matrix[:3, 0], matrix[:3, 1] = a / 2, bb / 2
        matrix[:3, 2] = n / np.linalg.norm(n)
        matrix[:3, 3] = ul + (a + bb) / 2
        scene[f"billboard{i}"] = {
            "type": "rectangle",
            "to_world": mi.ScalarTransform4f(matrix.tolist()),
        }
    return scene


def run_mitsuba(variant: str, data: dict, repeats: int) -> dict:
    """In this (child) process: load and render with one Mitsuba variant."""
    import mitsuba as mi

    mi.set_variant(variant)
    start = time.perf_counter()
    scene = mi.load_dict(mitsuba_dict(data, mi))
    load = time.perf_counter() - start
    start = time.perf_counter()
    image = np.array(mi.render(scene, spp=1))
    first = time.perf_counter() - start
    _, render_time = median_time(lambda: np.array(mi.render(scene, spp=1)), repeats)
    return {
        "load": load,
        "first": first,
        "render": render_time,
        "hit": (image[..., 0] > 0).tolist(),
    }


def mitsuba_in_child(variant: str, data: dict, repeats: int) -> dict | str:
    env = dict(os.environ)
    if variant.startswith("llvm") and Path(LLVM_19).exists():
        env.setdefault("DRJIT_LIBLLVM_PATH", LLVM_19)
    run = subprocess.run(
        [sys.executable, __file__, "--child", variant, "--repeats", str(repeats)],
        input=json.dumps(data),
        capture_output=True,
        text=True,
        env=env,
        timeout=1800,
    )
    if run.returncode != 0:
        last = (run.stderr.strip().splitlines() or [f"exit status {run.returncode}"])[-1]
        return f"failed: {last[:80]}"
    return json.loads(run.stdout)


def _engines(engine: str) -> list[str]:
    """The raykit engines to time: both for ``auto`` (compiled only where numba is installed)."""
    from raykit.engine.choice import compiled_available

    if engine == "auto":
        return ["numpy", "compiled"] if compiled_available() else ["numpy"]
    return [engine]


def plot(path: Path, rows: list[dict]) -> None:
    """The render medians as bars: a group per scene, a bar per renderer. ``rows``:
    ``{"scene", "renderer", "render"}`` (seconds, or None for a variant that failed)."""
    scenes = list(dict.fromkeys(row["scene"] for row in rows))
    renderers = list(dict.fromkeys(row["renderer"] for row in rows))
    times = {(row["scene"], row["renderer"]): row["render"] for row in rows}
    bar_plot(
        path,
        scenes,
        {r: [times.get((s, r)) for s in scenes] for r in renderers},
        "render time, median (ms, log scale)",
        "raykit against Mitsuba 3, 1 sample per pixel",
        log=True,
    )


def main() -> None:
    parser = arguments(__doc__, "small scenes")
    parser.add_argument("--plot", type=Path, help="write the render medians as bars here")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument(
        "--engine",
        choices=ENGINES,
        default="auto",
        help="raykit's engine: numpy, compiled, or auto: both side by side (default)",
    )
    if "--child" in sys.argv:  # one Mitsuba variant, for the parent: JSON only on stdout
        args = parser.parse_args()
        print(json.dumps(run_mitsuba(args.child, json.loads(sys.stdin.read()), args.repeats)))
        return
    args = parse(parser)
    try:
        import mitsuba

        version = mitsuba.__version__
    except ImportError:
        print("Mitsuba 3 is not installed (pip install mitsuba): raykit alone is timed.\n")
        version = None
    engines = _engines(args.engine)
    print(
        "| scene | renderer | load | prepare | first render | render (median) "
        "| load + prepare + render | render / Mitsuba llvm | hit masks agree |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    rows, compiled_renders, loaded = [], {}, {}
    for name, scene in benchmark_scenes(args.quick).items():
        data = scene_data(scene)
        loaded[name] = scene_from_dict(data)
        table, ours = [], None
        for engine in engines:
            load, prepare, first, took, ours = time_raykit(engine, data, args.repeats)
            table.append((f"raykit {engine}", load, prepare, first, took, "-"))
            if engine == "compiled":
                compiled_renders[name] = (load + prepare, took)
        for variant in VARIANTS if version is not None else ():
            result = mitsuba_in_child(variant, data, args.repeats)
            renderer = f"Mitsuba {version} {variant}"
            if isinstance(result, str):
                table.append((renderer, result, None, None, None, ""))
                continue
            agree = f"{np.mean(np.array(result['hit']) == ours):.1%}"
            table.append((renderer, result["load"], 0.0, result["first"], result["render"], agree))
        llvm = next((r[4] for r in table if r[0].endswith("llvm_ad_rgb") and r[4]), None)
        for renderer, load, prepare, first, took, agree in table:
            rows.append({"scene": name, "renderer": renderer, "render": took})
            if isinstance(load, str):
                print(f"| {name} | {renderer} | {load} | | | | | | |")
                continue
            ratio = f"{took / llvm:.2f}" if llvm else "-"
            print(
                f"| {name} | {renderer} | {seconds(load, 1)} "
                f"| {seconds(prepare, 1) if prepare else '-'} | {seconds(first, 1)} "
                f"| {seconds(took, 1)} | {seconds(load + prepare + took, 1)} | {ratio} | {agree} |"
            )
    print(
        f"\nMedians of {args.repeats} renders after a warm-up; load and render in one process each."
        " raykit compiled: prepare is raykit.engine.compiled.prepare (arrays, screen tiles, BVH"
        " for lit scenes), made once per scene as Mitsuba builds its BVH in load_dict; render"
        " renders the prepared scene. raykit.render.render(scene) does both; the numpy engine"
        " prepares inside its render."
    )
    growth(loaded, compiled_renders, args.repeats)
    if args.plot:
        plot(args.plot, rows)


def time_raykit(engine: str, data: dict, repeats: int) -> tuple:
    """raykit's times on one scene: ``(load, prepare, first render, render median, hit mask)``.
    The compiled engine's first render is a whole ``render(scene)`` (it loads the cached
    kernels, as Mitsuba's first render compiles its own), then prepare and render are medians;
    prepare is 0 for the numpy engine, which prepares inside its render."""
    start = time.perf_counter()
    loaded = scene_from_dict(data)
    load = time.perf_counter() - start
    if engine != "compiled":
        start = time.perf_counter()
        first_image = render(loaded, engine=engine)
        first = time.perf_counter() - start
        _, took = median_time(lambda: render(loaded, engine=engine), repeats)
        return load, 0.0, first, took, first_image.object_index >= 0
    from raykit.engine import compiled

    start = time.perf_counter()
    _, index, _ = compiled.render(loaded)
    first = time.perf_counter() - start
    prepared, prepare = median_time(lambda: compiled.prepare(loaded), repeats)
    _, took = median_time(lambda: compiled.render(prepared), repeats)
    return load, prepare, first, took, index >= 0


def growth(scenes: dict[str, Scene], compiled_renders: dict, repeats: int) -> None:
    """The issue's growth goals for the compiled engine: sphereflake 4 to 6 (81x the spheres)
    at most 3x the render time, and level 6 loaded, prepared and rendered within 2 s (from its
    row). The render ratio is timed here, the two prepared scenes rendered in turns, 3 x
    ``repeats`` rounds, each timed render right after an untimed one of the same scene
    (:func:`common.interleaved_medians`): in three runs of the table at commit 1bd1483,
    sphereflake 4's median alone took 4.4, 5.5 and 7.8 ms, as the machine's other work came and
    went, and the ratio of the rows 1.62 to 3.25."""
    names = {
        level: next(
            (name for name in compiled_renders if name.startswith(f"sphereflake {level}")), None
        )
        for level in (4, 6)
    }
    if None in names.values():
        return
    from raykit.engine import compiled

    prepared = {level: compiled.prepare(scenes[name]) for level, name in names.items()}
    renders = {level: (lambda p=p: compiled.render(p)) for level, p in prepared.items()}
    medians = interleaved_medians(renders, 3 * repeats, warm=True)
    level6_loaded = compiled_renders[names[6]]
    print(
        f"\nGrowth, raykit compiled: sphereflake 6 renders in {medians[6] / medians[4]:.2f}x the "
        f"time of sphereflake 4 ({seconds(medians[6], 1)} against {seconds(medians[4], 1)}, "
        f"medians of {3 * repeats} renders of each in turns, each after one untimed; goal: 3x "
        f"or less); level 6 loads, "
        f"prepares and renders in {level6_loaded[0] + level6_loaded[1]:.2f} s (goal: 2 s or less)."
    )


if __name__ == "__main__":
    main()

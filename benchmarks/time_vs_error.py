"""Run time against error: supersampling n x n everywhere, or only at edges (adaptive).

    python benchmarks/time_vs_error.py [--quick] [--repeats N] [--plot pareto.png]

For n = 1, 2, 4, 8 (1, 4, 16, 64 rays per pixel) and the adaptive mode, the RMS error of the
image against a 16 x 16 (256 rays per pixel) reference and the median render time, side by side
in one run. The last column compares each time with full 4 x 4 (16 rays per pixel). Two scenes:
the fence-heavy ``cutouts.json``, whose edges are a few percent of its pixels, and a
sphereflake, where thousands of small spheres make edges of a fifth of them.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from raykit.engine.adaptive import edge_pixels
from raykit.io.scene_json import load_scene
from raykit.render import render
from raykit.scene import Scene

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import arguments, loglog_plot, median_time, parse, sized  # noqa: E402

from scenes import sphereflake  # noqa: E402


def measure(scene: Scene, repeats: int) -> list[tuple[str, int, float, float]]:
    """(mode, n, RMS error, median seconds) for every mode and n."""
    reference = render(scene, 16, engine="numpy").rgb
    rows = []
    for adaptive in (False, True):
        for n in (1, 2, 4, 8):
            if adaptive and n == 1:
                continue
            image, seconds = median_time(
                lambda n=n, a=adaptive: render(scene, n, adaptive=a, engine="numpy"), repeats
            )
            error = float(np.sqrt(np.mean((image.rgb - reference) ** 2)))
            rows.append(("adaptive" if adaptive else "everywhere", n, error, seconds))
    return rows


def main() -> None:
    parser = arguments(__doc__, "small images, for CI", repeats=3)
    parser.add_argument("--plot", type=Path, help="write time against error here")
    args = parse(parser)
    cutouts = load_scene(HERE.parent / "scenes" / "cutouts.json")
    if args.quick:
        scenes = {
            "scenes/cutouts.json": sized(cutouts, 96, 64),
            "sphereflake 2": sphereflake(2, 64, 64),
        }
    else:
        scenes = {"scenes/cutouts.json": cutouts, "sphereflake 4": sphereflake(4, 256, 256)}
    series = {}
    for name, scene in scenes.items():
        rows = measure(scene, args.repeats)
        base = next(r[3] for r in rows if r[0] == "everywhere" and r[1] == 4)
        camera = scene.camera
        first = render(scene, engine="numpy")
        edges = edge_pixels(first.rgb, first.object_index).mean()
        print(
            f"{name} at {camera.width}x{camera.height}, {edges:.0%} of its pixels edges; "
            f"error against 16 x 16; medians of {args.repeats} runs\n"
        )
        print("| samples | where | rays per pixel | RMS error | time | time / full 4x4 |")
        print("|---|---|---|---|---|---|")
        for mode, n, error, seconds in rows:
            print(
                f"| {n} x {n} | {mode} | {n * n} | {error:.5f} | {seconds * 1000:.0f} ms "
                f"| {seconds / base:.2f} |"
            )
        print()
        for mode, style in (("everywhere", "s--"), ("adaptive", "o-")):
            series[f"{name.removeprefix('scenes/')}, {mode}"] = (
                [r[3] for r in rows if r[0] == mode],
                [r[2] for r in rows if r[0] == mode],
                style,
            )
    if args.plot:
        loglog_plot(args.plot, series, "render time (s)", "RMS error against 16 x 16")


if __name__ == "__main__":
    main()

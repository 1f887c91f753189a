"""Image order against object order, side by side, as the number of objects grows.

    python benchmarks/object_order.py [--quick] [--repeats N] [--plot object_order.png]

The slide's two loops on the same random spheres (``scenes.many_spheres``, 640x360; --quick:
160x90), each the median of ``--repeats`` runs, and the same object-index image both ways
(checked on every run):

* image order, tiles: ``raykit.render.render`` (for each pixel, the objects that can be seen
  in its tile);
* image order, every object: ``render(scene, skip_hidden=False)`` (for each pixel, every
  object), not run beyond ``EVERY_OBJECT_LIMIT`` ray-object tests;
* object order: ``raykit.object_order.render_object_order`` (for each object, the pixels its
  screen rectangle covers, a depth buffer).

Beside the times, the (object, pixel) tests each loop makes: pixels x objects for every
object, the pixels of every object's rectangle for object order.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import arguments, loglog_plot, median_time, parse, seconds  # noqa: E402

from raykit.engine.screen_bounds import object_bounds  # noqa: E402
from raykit.object_order import covered_pixels, render_object_order  # noqa: E402
from raykit.render import render  # noqa: E402
from scenes import many_spheres  # noqa: E402

EVERY_OBJECT_LIMIT = 3e7  # rays x objects beyond which "every object" is not run


def object_order_tests(scene) -> int:
    """How many (object, pixel) pairs object order intersects: its rectangles' pixels."""
    camera = scene.camera
    total = 0
    for row in object_bounds(camera, scene.objects):
        if not np.isnan(row).any():
            total += len(covered_pixels(tuple(row), camera.width, camera.height)[0])
    return total


def measure(count: int, size: tuple[int, int], repeats: int) -> dict:
    scene = many_spheres(count, *size, seed=19)
    pixels = size[0] * size[1]
    row = {"objects": count, "pairs every": pixels * count, "pairs object": 0}
    traced, row["tiles"] = median_time(lambda: render(scene, engine="numpy"), repeats)
    drawn, row["object order"] = median_time(lambda: render_object_order(scene), repeats)
    assert (traced.object_index == drawn.object_index).all(), "the loops disagree"
    row["every"] = None
    if pixels * count <= EVERY_OBJECT_LIMIT:
        row["every"] = median_time(
            lambda: render(scene, skip_hidden=False, engine="numpy"), repeats
        )[1]
    row["pairs object"] = object_order_tests(scene)
    return row


def main() -> None:
    parser = arguments(__doc__, "small images and few objects, for CI")
    parser.add_argument("--plot", type=Path, help="write time against number of objects here")
    args = parse(parser)
    size = (160, 90) if args.quick else (640, 360)
    counts = (1, 10, 100) if args.quick else (1, 3, 10, 30, 100, 300, 1000, 3000, 10000)
    rows = [measure(count, size, args.repeats) for count in counts]
    print(
        "| objects | image order, tiles | image order, every object | object order "
        "| object order / tiles | tests, every object | tests, object order |"
    )
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        print(
            f"| {row['objects']:,} | {seconds(row['tiles'], 1)} | {seconds(row['every'], 1)} "
            f"| {seconds(row['object order'], 1)} | {row['object order'] / row['tiles']:.2f} "
            f"| {row['pairs every']:,} | {row['pairs object']:,} |"
        )
    print(
        f"\nRandom spheres at {size[0]}x{size[1]}, medians of {args.repeats} runs; the same "
        "object-index image both ways on every row. 'not run': over "
        f"{EVERY_OBJECT_LIMIT:.0e} ray-object tests."
    )
    if args.plot:
        series = {
            "image order (tiles)": (counts, [r["tiles"] for r in rows], "o-"),
            "object order": (counts, [r["object order"] for r in rows], "s-"),
        }
        every = [(r["objects"], r["every"]) for r in rows if r["every"]]
        series["image order (every object)"] = (
            [p[0] for p in every],
            [p[1] for p in every],
            "^--",
        )
        loglog_plot(args.plot, series, "objects (random spheres)", "render time (s)")


if __name__ == "__main__":
    main()

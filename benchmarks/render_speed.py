"""Render time of raykit's variants, side by side in one run.

    python benchmarks/render_speed.py [--quick] [--repeats N] [--plot time_vs_objects.png]

Variants, on the same scene in the same process:

* per-pixel loop: a Python loop over pixels calling the same ray and intersection code for
  one ray at a time (what a first renderer looks like). Timed on a crop of 32 x 24 pixels
  (--quick: 8 x 6) and scaled to the whole image, as the table says.
* every object: each object tested against every pixel's ray (``skip_hidden=False``).
* tiles: each 128 x 128 tile tested only against the objects that can be seen in it (default).

Then float32 against float64 on every scene, and the whole process: ``raykit render`` of the
classic scene from the command line against ``python -c "import numpy, PIL.Image"``, run in
turn, each the median of ``--repeats`` runs (at least 5), and where its time goes: the same
steps in a fresh process, each timed (``--whole-process``: only these two tables).

Times are medians of ``--repeats`` runs of the render alone (not loading); the ratio columns
compare the variants measured in this run. ``--quick`` uses small images and few objects, for CI.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import arguments, loglog_plot, median_time, parse, seconds, sized  # noqa: E402

from raykit.camera import rays_through  # noqa: E402
from raykit.io.scene_json import load_scene  # noqa: E402
from raykit.render import cast, render  # noqa: E402
from raykit.scene import Scene  # noqa: E402
from scenes import many_spheres, sphereflake  # noqa: E402

CROP = (32, 24)  # pixels the per-pixel loop renders (--quick: 8 x 6), scaled up to the image
EVERY_OBJECT_LIMIT = 3e8  # rays x objects beyond which "every object" is not run (minutes)
WHOLE_PROCESS_GOAL = 1.5  # the whole process against the yardstick, as issue #18 asks


def per_pixel_loop(scene: Scene, crop: tuple[int, int]) -> None:
    """The first renderer: one ray at a time, over a crop in the middle of the image."""
    camera = scene.camera
    width, height = min(crop[0], camera.width), min(crop[1], camera.height)
    left, top = (camera.width - width) // 2, (camera.height - height) // 2
    for r in range(top, top + height):
        for c in range(left, left + width):
            cast(scene, *rays_through(camera, np.array([c + 0.5]), np.array([r + 0.5])))


def measure(name: str, scene: Scene, repeats: int, crop: tuple[int, int]) -> dict:
    camera = scene.camera
    pixels = camera.width * camera.height
    cropped = min(crop[0], camera.width) * min(crop[1], camera.height)
    row = {"scene": name, "size": f"{camera.width}x{camera.height}", "objects": len(scene.objects)}
    row["loop"] = median_time(lambda: per_pixel_loop(scene, crop), 1)[1] * pixels / cropped
    if pixels * len(scene.objects) <= EVERY_OBJECT_LIMIT:
        row["every"] = median_time(
            lambda: render(scene, skip_hidden=False, engine="numpy"), repeats
        )[1]
    else:
        row["every"] = None
    row["tiles"] = median_time(lambda: render(scene, engine="numpy"), repeats)[1]
    return row


# what ``raykit render scenes/classic.json -o OUT`` does (raykit.cli), step by step, in a fresh
# process: each step's seconds, one per line
STEPS = """
import sys, time
start = time.perf_counter()
import numpy, PIL.Image
imported = time.perf_counter()
import raykit.cli
from raykit.io.images import check_image_path, save_image
from raykit.io.scene_json import load_scene
from raykit.render import render
ready = time.perf_counter()
check_image_path(sys.argv[2])
scene = load_scene(sys.argv[1])
loaded = time.perf_counter()
image = render(scene)
rendered = time.perf_counter()
save_image(image.rgb, sys.argv[2])
saved = time.perf_counter()
for a, b in ((start, imported), (imported, ready), (ready, loaded), (loaded, rendered),
             (rendered, saved)):
    print(b - a)
"""
STEP_NAMES = (
    "importing numpy and Pillow",
    "importing raykit's modules",
    "loading the scene (JSON, textures)",
    "rendering (numpy engine, first render in the process)",
    "writing the PNG",
)


def whole_process(repeats: int) -> tuple[float, float, float, list[float]]:
    """Median wall times (s) of a Python that imports numpy and Pillow, of ``raykit render`` of
    the classic scene to a PNG and of ``python -c pass``, and the median seconds of each of
    :data:`STEP_NAMES` in a process doing what ``raykit render`` does: each a fresh process,
    the four run in turn."""
    classic = str(HERE.parent / "scenes" / "classic.json")
    with tempfile.TemporaryDirectory() as folder:
        image = f"{folder}/classic.png"
        timed = (
            [sys.executable, "-c", "import numpy, PIL.Image"],
            [sys.executable, "-m", "raykit", "render", classic, "-o", image],
            [sys.executable, "-c", "pass"],
        )
        walls, steps = ([], [], []), []
        for _ in range(repeats):
            for command, kept in zip(timed, walls, strict=True):
                start = time.perf_counter()
                subprocess.run(command, check=True, capture_output=True)
                kept.append(time.perf_counter() - start)
            done = subprocess.run(
                [sys.executable, "-c", STEPS, classic, image],
                check=True, capture_output=True, text=True,
            )  # fmt: skip
            steps.append([float(line) for line in done.stdout.split()])
    imports, whole, python = (statistics.median(kept) for kept in walls)
    return imports, whole, python, [statistics.median(step) for step in zip(*steps, strict=True)]


def print_whole_process(repeats: int) -> None:
    imports, whole, python, steps = whole_process(repeats)
    print("| whole process, classic 640x480 | median | ratio |")
    print("|---|---|---|")
    print(f'| `python -c "import numpy, PIL.Image"` | {seconds(imports)} | 1.00 |')
    print(f"| `raykit render scenes/classic.json` | {seconds(whole)} | {whole / imports:.2f} |")

    print("\n| where `raykit render scenes/classic.json` spends its time | median |")
    print("|---|---|")
    print(f"| Python starting (`python -c pass`) | {seconds(python)} |")
    for name, step in zip(STEP_NAMES, steps, strict=True):
        print(f"| {name} | {seconds(step)} |")
    print(
        f"\nA whole process of {WHOLE_PROCESS_GOAL} times the first table's yardstick leaves "
        f"{seconds((WHOLE_PROCESS_GOAL - 1) * imports)} for everything beyond importing numpy "
        f"and Pillow; raykit's own steps took {seconds(sum(steps[1:]))} here, the render alone "
        f"{seconds(steps[3])}."
    )


def scenes(quick: bool) -> list[tuple[str, Scene]]:
    classic = load_scene(HERE.parent / "scenes" / "classic.json")
    if quick:
        small = sized(classic, 160, 120)
        return [
            ("classic", small),
            ("sphereflake 2", sphereflake(2, 128, 128)),
            ("100 spheres", many_spheres(100, 240, 135)),
        ]
    return [
        ("classic", classic),
        ("sphereflake 2", sphereflake(2)),
        ("sphereflake 3", sphereflake(3)),
        ("sphereflake 4", sphereflake(4)),
        ("1,000 spheres", many_spheres(1000)),
    ]


def example_scenes(quick: bool) -> list[tuple[str, Scene]]:
    """Every example scene of the repository (small in --quick), for the float32 comparison."""
    found = []
    for path in sorted((HERE.parent / "scenes").glob("*.json")):
        scene = load_scene(path)
        if quick:
            scene = sized(scene, 64, 48)
        found.append((f"scenes/{path.name}", scene))
    return found


def main() -> None:
    parser = arguments(__doc__, "small images, for CI")
    parser.add_argument("--plot", type=Path, help="write time against number of objects here")
    parser.add_argument(
        "--whole-process", action="store_true", help="only the whole process and its steps"
    )
    args = parse(parser)
    if args.whole_process:
        print_whole_process(max(args.repeats, 5))
        return
    crop = (8, 6) if args.quick else CROP
    rows = [measure(name, scene, args.repeats, crop) for name, scene in scenes(args.quick)]

    print(
        "| scene | image | objects | per-pixel loop* | every object | tiles "
        "| every object / tiles | loop / tiles |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for row in rows:
        versus = f"{row['every'] / row['tiles']:.1f}x" if row["every"] else "-"
        print(
            f"| {row['scene']} | {row['size']} | {row['objects']:,} | {seconds(row['loop'])} "
            f"| {seconds(row['every'])} | {seconds(row['tiles'])} | {versus} "
            f"| {row['loop'] / row['tiles']:.0f}x |"
        )
    print(
        f"\n* per-pixel loop: a Python loop over pixels calling raykit's own functions with one "
        f"ray at a time, timed on a {crop[0]} x {crop[1]} crop and scaled to the image. "
        f"Medians of {args.repeats} runs (the loop: 1). 'not run': over "
        f"{EVERY_OBJECT_LIMIT:.0e} ray-object tests."
    )

    print("\n| scene | float64 | float32 | float32 / float64 | pixels whose object changes |")
    print("|---|---|---|---|---|")
    for name, scene in scenes(args.quick) + example_scenes(args.quick):
        double, t64 = median_time(lambda s=scene: render(s, engine="numpy"), args.repeats)
        single, t32 = median_time(lambda s=scene: render(s, dtype=np.float32), args.repeats)
        changed = int((double.object_index != single.object_index).sum())
        print(
            f"| {name} | {seconds(t64)} | {seconds(t32)} | {t32 / t64:.2f} "
            f"| {changed} of {double.object_index.size:,} |"
        )

    print()
    print_whole_process(max(args.repeats, 5))

    if args.plot:
        flakes = [r for r in rows if r["scene"].startswith("sphereflake")]
        series = {}
        for key, label, style in (("every", "every object", "s--"), ("tiles", "tiles", "o-")):
            points = [(r["objects"], r[key]) for r in flakes if r[key]]
            series[label] = ([p[0] for p in points], [p[1] for p in points], style)
        loglog_plot(args.plot, series, "objects (sphereflake levels)", "render time (s)")


if __name__ == "__main__":
    main()

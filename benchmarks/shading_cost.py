"""What shading costs, and what skipping saves, side by side in one run.

    python benchmarks/shading_cost.py [--quick] [--repeats N] [--plot shading_cost.png]

Table 1, per scene: the render with its lights, shadows and mirrors, against the same scene
with them taken away (flat colours, as in scene format v1) and against the same render with
every shadow ray tested against every object (no culling by
:func:`raykit.engine.regions.cast_nearby`); and the secondary rays cast (counted by wrapping the
caster :func:`raykit.shading.shade` is given in a :class:`raykit.diagrams.rays.RecordingCaster`).

Table 2, secondary rays through the BVH against brute force (``cast`` over every object), on
lit sphereflakes with every ball a weak mirror: the renderer picks the BVH from
``raykit.engine.regions.BVH_FROM`` objects on.

Times are medians of ``--repeats`` renders (not loading). ``--quick`` uses small images.
``--plot`` draws table 1's times as bars per scene.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import arguments, bar_plot, median_time, parse, seconds, sized  # noqa: E402

import raykit.engine.regions  # noqa: E402
import raykit.render  # noqa: E402
from raykit.diagrams.rays import RecordingCaster  # noqa: E402
from raykit.engine.bvh import BVH  # noqa: E402
from raykit.io.scene_json import load_scene  # noqa: E402
from raykit.lights import DirectionalLight, PointLight  # noqa: E402
from raykit.materials import PLAIN, Material  # noqa: E402
from raykit.render import cast, cast_pixels, render, secondary_caster  # noqa: E402
from raykit.scene import Scene  # noqa: E402
from raykit.shading import shade  # noqa: E402
from scenes import sphereflake  # noqa: E402

EXAMPLES = ["classic_lit", "shadow_on_billboard", "mirror_balls"]


def unlit(scene: Scene) -> Scene:
    """The scene without lights, ambient light or materials: v1's flat colours."""
    plain = {"material": PLAIN}
    return replace(
        scene,
        lights=(),
        ambient=None,
        spheres=tuple(replace(s, **plain) for s in scene.spheres),
        billboards=tuple(replace(b, **plain) for b in scene.billboards),
    )


def secondary_rays(scene: Scene) -> dict[str, int]:
    camera = scene.camera
    rows, cols = np.divmod(np.arange(camera.width * camera.height), camera.width)
    origins, directions, hits = cast_pixels(scene, rows, cols)
    recorder = RecordingCaster(secondary_caster(scene))
    shade(scene, recorder, origins, directions, hits)
    count = {"shadow": 0, "mirror": 0}
    for p in recorder.segments:
        count[p.kind] += len(p.t)
    return count


def lit_flake(level: int, size: int) -> Scene:
    """A sphereflake under a sun and a lamp, every ball a weak mirror."""
    flake = sphereflake(level, size, size)
    mirror = Material(specular=np.full(3, 0.5), shininess=40, mirror=np.full(3, 0.3))
    return replace(
        flake,
        spheres=tuple(replace(s, material=mirror) for s in flake.spheres),
        lights=(
            DirectionalLight(np.array([-0.5, -1.0, -0.4]), np.full(3, 0.7)),
            PointLight(np.array([3.0, 5.0, 4.0]), np.full(3, 0.4)),
        ),
        ambient=np.full(3, 0.15),
        max_depth=2,
    )


def every_object(scene: Scene, cast_scene=cast, arrays=None):
    """The brute-force caster: every object tested against every secondary ray."""
    return lambda origins, directions, t_max=None: cast_scene(scene, origins, directions)


def bvh_caster(scene: Scene, cast_scene=cast, arrays=None):
    """The BVH's caster, whatever the number of objects."""
    return BVH.build(scene, arrays).cast


def plot(path: Path, rows: list[dict]) -> None:
    """Table 1 as bars: per scene, the flat, shaded and unculled render times (seconds)."""
    bar_plot(
        path,
        [row["scene"] for row in rows],
        {
            "flat (v1)": [row["flat"] for row in rows],
            "shaded": [row["shaded"] for row in rows],
            "shaded, no culling": [row["unculled"] for row in rows],
        },
        "render time (ms)",
        f"what shading costs, {rows[0]['image']}" if rows else "",
    )


def main() -> None:
    parser = arguments(__doc__, "small images, for CI")
    parser.add_argument("--plot", type=Path, help="write table 1's times as bars here")
    args = parse(parser)
    width, height = (160, 120) if args.quick else (640, 480)
    scenes_folder = HERE.parent / "scenes"

    print(
        "| scene | image | flat (v1) | shaded | shaded / flat | shaded, no culling "
        "| no culling / shaded | shadow rays | mirror rays |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    original = raykit.engine.regions.secondary_caster
    rows = []
    for name in ["classic", *EXAMPLES]:
        scene = sized(load_scene(scenes_folder / f"{name}.json"), width, height)
        flat_scene = unlit(scene)
        _, flat = median_time(lambda s=flat_scene: render(s, engine="numpy"), args.repeats)
        _, shaded = median_time(lambda s=scene: render(s, engine="numpy"), args.repeats)
        raykit.engine.regions.secondary_caster = every_object
        _, unculled = median_time(lambda s=scene: render(s, engine="numpy"), args.repeats)
        raykit.engine.regions.secondary_caster = original
        rays = secondary_rays(scene)
        rows.append(
            {"scene": name, "image": f"{width}x{height}", "flat": flat, "shaded": shaded}
            | {"unculled": unculled}
        )
        print(
            f"| {name} | {width}x{height} | {seconds(flat)} | {seconds(shaded)} "
            f"| {shaded / flat:.2f} | {seconds(unculled)} | {unculled / shaded:.2f} "
            f"| {rays['shadow']:,} | {rays['mirror']:,} |"
        )

    size = 128 if args.quick else 256
    levels = [2] if args.quick else [2, 3]
    print("\n| lit sphereflake | image | objects | brute force | BVH | brute / BVH |")
    print("|---|---|---|---|---|---|")
    for level in levels:
        scene = lit_flake(level, size)
        raykit.engine.regions.secondary_caster = every_object
        brute_image, brute = median_time(lambda s=scene: render(s, engine="numpy"), args.repeats)
        raykit.engine.regions.secondary_caster = bvh_caster
        bvh_image, through_bvh = median_time(
            lambda s=scene: render(s, engine="numpy"), args.repeats
        )
        raykit.engine.regions.secondary_caster = original
        assert np.array_equal(brute_image.rgb, bvh_image.rgb)
        print(
            f"| level {level} | {size}x{size} | {len(scene.objects):,} | {seconds(brute)} "
            f"| {seconds(through_bvh)} | {brute / through_bvh:.1f}x |"
        )
    print(f"\nMedians of {args.repeats} renders; the two variants give the same image (checked).")
    if args.plot:
        plot(args.plot, rows)


if __name__ == "__main__":
    main()

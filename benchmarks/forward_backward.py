"""Forward against backward: error against time for the direct diffuse term.

    python benchmarks/forward_backward.py [--quick] [--repeats N] [--plot forward_backward.png]

The same quantity both ways (:mod:`raykit.forward`): the direct diffuse term of
``scenes/shadow_on_billboard.json`` (one point light, shadows), each pixel's area average, at
160x120 (--quick: 40x30). The reference is the backward render with 16 x 16 samples per pixel.

* backward: ``render(diffuse_only(scene), samples=n)`` for n = 1, 2, 4, 8 (a ray per sample
  from the eye, a shadow ray to the light);
* forward: ``forward_render(scene, photons)`` from 10,000 photons up, seeded (photons from the
  light, one diffuse bounce, counted where they land on the image).

Each row: median time of ``--repeats`` runs, RMS error against the reference, and for forward
the share of photons that hit anything, that land on the image, and that a random bounce would
send through a real 1 mm pinhole.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import arguments, loglog_plot, median_time, parse, seconds, sized  # noqa: E402

from raykit.forward import diffuse_only, forward_render  # noqa: E402
from raykit.io.scene_json import load_scene  # noqa: E402
from raykit.render import render  # noqa: E402


def main() -> None:
    parser = arguments(__doc__, "a small image and few photons, for CI")
    parser.add_argument("--plot", type=Path, help="write error against time here")
    args = parse(parser)
    scene = load_scene(HERE.parent / "scenes" / "shadow_on_billboard.json")
    size = (40, 30) if args.quick else (160, 120)
    scene = sized(scene, *size)
    diffuse = diffuse_only(scene)
    reference = render(diffuse, samples=16, engine="numpy").rgb

    def rms(image: np.ndarray) -> float:
        return float(np.sqrt(np.mean((image - reference) ** 2)))

    print(
        "| direction | work | time | RMS error | hit a surface | land on the image "
        "| through a 1 mm pinhole |"
    )
    print("|---|---|---|---|---|---|---|")
    backward = []
    for n in (1, 2) if args.quick else (1, 2, 4, 8):
        image, elapsed = median_time(
            lambda n=n: render(diffuse, samples=n, engine="numpy").rgb, args.repeats
        )
        backward.append((elapsed, rms(image)))
        print(
            f"| backward | {n} x {n} samples per pixel | {seconds(elapsed, 1)} "
            f"| {rms(image):.4f} | - | - | - |"
        )
    forward = []
    counts = (10_000, 40_000) if args.quick else (10_000, 40_000, 160_000, 640_000, 2_560_000)
    for photons in counts:
        (image, stats), elapsed = median_time(
            lambda p=photons: forward_render(scene, p, seed=19), args.repeats
        )
        forward.append((elapsed, rms(image)))
        print(
            f"| forward | {photons:,} photons | {seconds(elapsed, 1)} | {rms(image):.4f} "
            f"| {stats.hit / stats.emitted:.1%} | {stats.landed / stats.emitted:.1%} "
            f"| {stats.through_hole / stats.emitted:.1e} |"
        )
    print(
        f"\n{size[0]}x{size[1]} pixels; the reference is backward with 16 x 16 samples per "
        f"pixel; medians of {args.repeats} runs."
    )
    if args.plot:
        series = {
            "backward (n x n samples)": ([b[0] for b in backward], [b[1] for b in backward], "o-"),
            "forward (photons)": ([f[0] for f in forward], [f[1] for f in forward], "s-"),
        }
        loglog_plot(args.plot, series, "time (s)", "RMS error against the reference")


if __name__ == "__main__":
    main()

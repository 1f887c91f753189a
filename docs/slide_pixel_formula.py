"""What a student who used the slide's second pixel formula would render, measured.

    python docs/slide_pixel_formula.py

The slide's u_i = i·2/N_cols, i = 0, ±1, ±2, …, ±N_cols/2 gives N_cols + 1 positions for
N_cols pixels (:func:`raykit.linescan.camera.slide_pixel_positions`). Fitting them to N pixels, a
student keeps the first N (u = -1 + c·2/N: every ray through a pixel's left/top edge, the image
shifted half a pixel), the last N (the other edge), or spreads all N + 1 over the N pixels
(u from -1 to 1 inclusive: stretched by N/(N - 1)). Each is rendered here with the renderer's
own image-point mapping patched (``raykit.engine.regions.region_points``, where the numpy engine
takes each pixel's point), on the example scenes and on
the classic scene made small, and compared with the correct render: the share of pixels whose
object changes, and the autograder's image comparison (3 x 3 neighbourhood, 2 levels).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path
from unittest import mock

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

import raykit.engine.regions  # noqa: E402
from raykit.camera import region_points  # noqa: E402
from raykit.io.images import quantize  # noqa: E402
from raykit.io.scene_json import load_scene  # noqa: E402
from raykit.render import render  # noqa: E402
from raykit_grading.kit.compare import compare_images  # noqa: E402


def slide_formula(variant: str, width: int, height: int):
    """A patch of the renderer's image points for one way of fitting N + 1 positions to N."""
    shift = {"first N": 0.0, "last N": 1.0}

    def points(rows, cols, a=0.5, b=0.5):
        x, y = region_points(rows, cols, 0.0, 0.0)  # pixel indices c, r
        if variant == "spread":
            return x * width / (width - 1), y * height / (height - 1)
        return x + shift[variant], y + shift[variant]

    return mock.patch.object(raykit.engine.regions, "region_points", points)


def main() -> None:
    scenes = [
        (name, load_scene(REPO / "scenes" / f"{name}.json"))
        for name in ("classic", "cutouts", "orthographic", "wide_fov")
    ]
    classic = scenes[0][1]
    for size in ((64, 48), (32, 24)):
        camera = replace(classic.camera, width=size[0], height=size[1])
        scenes.append((f"classic {size[0]}x{size[1]}", replace(classic, camera=camera)))
    print(f"{'scene':18s} {'variant':8s} {'objects changed':>16s} {'grader matched':>15s} score")
    for name, scene in scenes:
        reference = render(scene, skip_hidden=False, engine="numpy")
        for variant in ("first N", "last N", "spread"):
            with slide_formula(variant, scene.camera.width, scene.camera.height):
                # every object (the tiles' bounds assume centres), in the engine patched
                got = render(scene, skip_hidden=False, engine="numpy")
            changed = (got.object_index != reference.object_index).mean()
            comparison = compare_images(quantize(got.rgb), quantize(reference.rgb))
            print(
                f"{name:18s} {variant:8s} {changed:16.2%} {comparison.fraction:15.4f} "
                f"{comparison.score():.2f}"
            )


if __name__ == "__main__":
    main()

"""Make the pictures of docs/gallery.md with raykit's own commands.

    python docs/make_gallery.py [OUT_FOLDER]

Writes the gallery's one scene file that is made in code, ``docs/gallery/sphereflake_lit.json``
(Eric Haines' sphereflake, ``benchmarks/scenes.py``, level 3, under a sun and a lamp, every ball
a weak mirror), then runs each ``raykit`` command of :data:`ENTRIES` (the commands the gallery
shows) into OUT_FOLDER (default: docs/gallery).
"""

from __future__ import annotations

import json
import os
import shlex
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
GALLERY = REPO / "docs" / "gallery"

# (title, scene file, raykit command line with {out} for the output folder, what it shows);
# renders as large as a projector wants them (1200 pixels wide or 675 high, --width)
ENTRIES = [
    (
        "Sphereflake with shadows and mirrors",
        "docs/gallery/sphereflake_lit.json",
        "render docs/gallery/sphereflake_lit.json -o {out}/sphereflake_lit.png --width 675",
        "820 balls, each a weak mirror with a highlight, under a sun and a lamp: shadows on "
        "the ground and between the balls, two mirror bounces (the BVH carries the secondary "
        "rays).",
    ),
    (
        "Classic, lit",
        "scenes/classic_lit.json",
        "render scenes/classic_lit.json -o {out}/classic_lit.png --samples 2 --width 900",
        "The classic scene under a sun and a lamp: Lambert, Blinn-Phong highlights, shadows.",
    ),
    (
        "Mirror balls",
        "scenes/mirror_balls.json",
        "render scenes/mirror_balls.json -o {out}/mirror_balls.png --samples 2 --width 1080",
        "Two mirror balls and a wall mirror, up to four bounces; the tree behind the camera is "
        "seen only in them.",
    ),
    (
        "Shadow on a billboard",
        "scenes/shadow_on_billboard.json",
        "render scenes/shadow_on_billboard.json -o {out}/shadow_on_billboard.png --samples 2"
        " --width 900",
        "A ball's shadow on a checkered billboard, a cut-out fence's shadow on the floor.",
    ),
    (
        "Classic",
        "scenes/classic.json",
        "render scenes/classic.json -o {out}/classic.png --samples 2 --width 900",
        "Balls and billboards, flat colours: the assignment's picture.",
    ),
    (
        "Cut-outs",
        "scenes/cutouts.json",
        "render scenes/cutouts.json -o {out}/cutouts.png --samples 3 --adaptive --width 1014",
        "Alpha cut-out trees and a fence; a billboard seen from behind, mirrored.",
    ),
    (
        "Orthographic",
        "scenes/orthographic.json",
        "render scenes/orthographic.json -o {out}/orthographic.png --samples 2 --width 675",
        "Parallel rays: no perspective, far balls as big as near ones.",
    ),
    (
        "Wide field of view",
        "scenes/wide_fov.json",
        "render scenes/wide_fov.json -o {out}/wide_fov.png --samples 2 --width 1200",
        "A 150° field of view from inside a ring of balls: linear perspective stretches the edges.",
    ),
    (
        "A passing car, swept",
        "scenes/linescan3d/passing_car.json",
        "sweep scenes/linescan3d/passing_car.json -o {out}/passing_car_sweep.png --scans 1200",
        "A camera one pixel high by the road, looking across it: the car drives through its "
        "plane of view, and the scans, stacked, are the car.",
    ),
    (
        "A conveyor, swept",
        "scenes/linescan/conveyor.json",
        "sweep scenes/linescan/conveyor.json -o {out}/conveyor_sweep.png",
        "An orthographic inspection camera over a belt: a part with a hole, one with a bad spot.",
    ),
]


def sphereflake_lit() -> dict:
    """The gallery's sphereflake: level 3 at 480x480, lit, shadows on, every ball a mirror."""
    sys.path.insert(0, str(REPO / "benchmarks"))
    from scenes import sphereflake_dict

    scene = sphereflake_dict(3, 480, 480)
    for sphere in scene["spheres"]:
        sphere.update(specular=[0.5, 0.5, 0.5], shininess=40, mirror=[0.3, 0.3, 0.3])
    scene.update(
        ambient=[0.15, 0.15, 0.15],
        max_depth=2,
        lights=[
            {"type": "directional", "direction": [-0.4, -1.0, -0.5], "color": [0.7, 0.7, 0.65]},
            {"type": "point", "position": [3.0, 5.0, 3.0], "color": [0.5, 0.5, 0.55]},
        ],
    )
    return scene


def make(folder: Path) -> None:
    from raykit.cli import main

    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    scene_file = GALLERY / "sphereflake_lit.json"
    scene_file.write_text(json.dumps(sphereflake_lit(), separators=(",", ":")) + "\n")
    here = Path.cwd()
    os.chdir(REPO)  # scene paths in the commands are relative to the repository
    try:
        for _, _, command, _ in ENTRIES:
            if main(shlex.split(command.format(out=folder))) != 0:
                raise SystemExit(f"failed: raykit {command}")
    finally:
        os.chdir(here)


if __name__ == "__main__":
    make(Path(sys.argv[1]) if len(sys.argv) > 1 else GALLERY)

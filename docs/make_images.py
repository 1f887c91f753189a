"""Make the pictures of README.md and the docs pages with raykit's own commands.

    python docs/make_images.py [OUT_FOLDER]

runs each ``raykit`` command below (the ones docs/rendering.md shows, with ``docs/images/`` as
the output folder) and writes into OUT_FOLDER (default: docs/images). The tests run it into a
temporary folder and compare the results with the committed images.
"""

from __future__ import annotations

import os
import shlex
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent

# raykit command lines, run from the repository's folder; {out} is the output folder
COMMANDS = [
    "render scenes/classic.json -o {out}/classic.png",
    "render scenes/cutouts.json -o {out}/cutouts.png --samples 3",
    "scan scenes/linescan/slide.json -o {out}/slide_scan.png --height 2 --scale 40"
    " --diagram {out}/slide_rays.png",
    "sweep scenes/linescan/passing_car.json -o {out}/passing_car_2d_sweep.png"
    " --diagram {out}/passing_car_sweep_diagram.png",
    "sweep scenes/linescan3d/passing_car.json -o {out}/passing_car_sweep.png --scans 480",
    "sweep scenes/linescan/conveyor.json -o {out}/conveyor_sweep.png",
    "diagram scenes/classic.json -o {out}/classic_rays_top.png --view top",
    "diagram scenes/cutouts.json -o {out}/cutouts_rays_side.png --view side --rays 60",
    "diagram scenes/classic.json -o {out}/classic_camera.png --view camera",
    "render scenes/classic_lit.json -o {out}/classic_lit.png",
    "render scenes/mirror_balls.json -o {out}/mirror_balls.png",
    "render scenes/shadow_on_billboard.json -o {out}/shadow_on_billboard.png",
    "diagram scenes/shadow_on_billboard.json -o {out}/shadow_rays_side.png --view side --rays 40",
    "diagram scenes/mirror_balls.json -o {out}/mirror_rays_top.png --view top --rays 60",
    "render scenes/soft_shadows.json -o {out}/soft_shadows.png",
    "render scenes/depth_of_field.json -o {out}/depth_of_field.png",
    "render scenes/glossy.json -o {out}/glossy.png",
    "render scenes/motion_blur.json -o {out}/motion_blur.png",
]

# figures that no command draws: (file name, function in raykit.diagrams.math_figures)
MATH_FIGURES = [
    ("math_sphere_cases.png", "sphere_cases"),
    ("math_plane_hit.png", "plane_hit"),
    ("math_dot_projection.png", "dot_projection"),
    ("math_plane_sides.png", "plane_sides"),
]

# the lecture's other figures: (file name, "module:function", the scene it is drawn for, args);
# named *_diagram, so the tests compare them as figures, not pixel for pixel
LECTURE_FIGURES = [
    ("pinhole_diagram.png", "raykit.diagrams.pinhole:pinhole_figure", "scenes/classic.json", ()),
    (
        "paths_of_light_diagram.png",
        "raykit.linescan.diagrams:paths_of_light",
        "scenes/linescan/slide.json",
        ((3.0, 4.5),),
    ),
    ("pixel_formulas_diagram.png", "raykit.linescan.diagrams:pixel_formulas", None, ()),
]


def outputs(command: str) -> list[str]:
    """The file names a command line writes (its -o and --diagram arguments)."""
    args = shlex.split(command)
    return [Path(args[i + 1]).name for i, a in enumerate(args) if a in ("-o", "--diagram")]


def make(folder: Path) -> None:
    from raykit.cli import main

    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    here = Path.cwd()
    os.chdir(REPO)  # scene paths in the commands are relative to the repository
    try:
        for command in COMMANDS:
            if main(shlex.split(command.format(out=folder))) != 0:
                raise SystemExit(f"failed: raykit {command}")
    finally:
        os.chdir(here)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from raykit.diagrams import math_figures
    from raykit.io.images import save_figure

    for name, function in MATH_FIGURES:
        figure = getattr(math_figures, function)()
        save_figure(figure, folder / name)
        plt.close(figure)
        print(f"wrote {folder / name}")

    import importlib

    from raykit.io.linescan_json import load_line_scene
    from raykit.io.scene_json import load_scene

    for name, target, scene_path, args in LECTURE_FIGURES:
        module, function = target.split(":")
        if scene_path is None:
            arguments = args
        else:
            loader = load_line_scene if "linescan" in scene_path else load_scene
            arguments = (loader(REPO / scene_path), *args)
        figure = getattr(importlib.import_module(module), function)(*arguments)
        save_figure(figure, folder / name)
        plt.close(figure)
        print(f"wrote {folder / name}")


def all_outputs() -> list[str]:
    """Every file name :func:`make` writes."""
    return (
        [n for c in COMMANDS for n in outputs(c)]
        + [n for n, _ in MATH_FIGURES]
        + [n for n, *_ in LECTURE_FIGURES]
    )


if __name__ == "__main__":
    make(Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "docs" / "images")

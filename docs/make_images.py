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

# raykit command lines, run from the repository's folder; {out} is the output folder. Renders
# are made as large as a projector wants them (docs/lecturers.md, "Figures a back row can
# read": 1200 pixels wide or 675 high), in the scene's proportions (--width); the 12 pixels of
# one scan are drawn as blocks that large (--scale), a picture of the pixels themselves.
COMMANDS = [
    "render scenes/classic.json -o {out}/classic.png --width 900",
    "render scenes/cutouts.json -o {out}/cutouts.png --samples 3 --width 1014",
    "scan scenes/linescan/slide.json -o {out}/slide_scan.png --height 2 --scale 160"
    " --diagram {out}/slide_rays.png",
    "sweep scenes/linescan/passing_car.json -o {out}/passing_car_2d_sweep.png"
    " --diagram {out}/passing_car_sweep_diagram.png",
    "sweep scenes/linescan3d/passing_car.json -o {out}/passing_car_sweep.png --scans 1200",
    "sweep scenes/linescan/conveyor.json -o {out}/conveyor_sweep.png",
    "diagram scenes/classic.json -o {out}/classic_rays_top.png --view top",
    "diagram scenes/cutouts.json -o {out}/cutouts_rays_side.png --view side --rays 60",
    "diagram scenes/classic.json -o {out}/classic_camera.png --view camera",
    "render scenes/classic_lit.json -o {out}/classic_lit.png --width 900",
    "render scenes/mirror_balls.json -o {out}/mirror_balls.png --width 1080",
    "render scenes/shadow_on_billboard.json -o {out}/shadow_on_billboard.png --width 900",
    "diagram scenes/shadow_on_billboard.json -o {out}/shadow_rays_side.png --view side --rays 40",
    "diagram scenes/mirror_balls.json -o {out}/mirror_rays_top.png --view top --rays 60",
    "render scenes/soft_shadows.json -o {out}/soft_shadows.png --width 900",
    "render scenes/depth_of_field.json -o {out}/depth_of_field.png --width 900",
    "render scenes/glossy.json -o {out}/glossy.png --width 1014",
    "render scenes/motion_blur.json -o {out}/motion_blur.png --width 1014",
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


# the renders whose full size takes tens of seconds: tests/test_reproducible.py renders them at
# the scene's own size (REDUCED_WIDTH) and holds the committed picture, scaled down, to that
REDUCED_WIDTH = {
    "cutouts.png": 480,
    "soft_shadows.png": 320,
    "depth_of_field.png": 320,
    "glossy.png": 240,
    "motion_blur.png": 240,
}


def reduced(command: str) -> str:
    """``command`` with its render at the width of REDUCED_WIDTH, if it is one of those."""
    for name, width in REDUCED_WIDTH.items():
        if f"/{name} " in command + " ":
            return " ".join(_with_width(shlex.split(command), width))
    return command


def _with_width(args: list[str], width: int) -> list[str]:
    at = args.index("--width")
    return [*args[: at + 1], str(width), *args[at + 2 :]]


def outputs(command: str) -> list[str]:
    """The file names a command line writes (its -o and --diagram arguments)."""
    args = shlex.split(command)
    return [Path(args[i + 1]).name for i, a in enumerate(args) if a in ("-o", "--diagram")]


def make(folder: Path, reduce: bool = False) -> None:
    """Run every command into ``folder``; ``reduce``: the REDUCED_WIDTH renders at that width."""
    from raykit.cli import main

    folder = Path(folder).resolve()
    folder.mkdir(parents=True, exist_ok=True)
    here = Path.cwd()
    os.chdir(REPO)  # scene paths in the commands are relative to the repository
    try:
        for command in COMMANDS:
            command = reduced(command) if reduce else command
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

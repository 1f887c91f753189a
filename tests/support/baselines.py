"""The figures whose pictures are pinned as baselines in tests/support/baseline_images/.

    python tests/support/baselines.py        # regenerate every baseline after a deliberate change

The tests draw each figure again and compare it with its baseline using matplotlib's own
``compare_images`` (RMS tolerance ``TOLERANCE``), so small anti-aliasing differences pass and
a moved ray, a lost label or a wrong colour does not.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

from raykit.diagrams import math_figures  # noqa: E402
from raykit.diagrams.camera import camera_diagrams  # noqa: E402
from raykit.diagrams.rays import ray_diagram as ray_diagram_3d  # noqa: E402
from raykit.io.linescan_json import load_line_scene  # noqa: E402
from raykit.io.scene_json import load_scene  # noqa: E402
from raykit.linescan.diagrams import ray_diagram, sweep_diagram  # noqa: E402

HERE = Path(__file__).resolve().parent
SCENES = HERE.parents[1] / "scenes"
FOLDER = HERE / "baseline_images"
TOLERANCE = 3.0
DPI = 60


def _linescan(name: str) -> object:
    return load_line_scene(SCENES / "linescan" / f"{name}.json")


def _scene(name: str) -> object:
    return load_scene(SCENES / f"{name}.json")


FIGURES = {
    "rays_classic_3d": lambda: ray_diagram_3d(_scene("classic"), view="3d"),
    "rays_classic_top": lambda: ray_diagram_3d(_scene("classic"), view="top"),
    "rays_cutouts_side": lambda: ray_diagram_3d(_scene("cutouts"), view="side", every=60),
    "camera_classic": lambda: camera_diagrams(_scene("classic").camera),
    "math_sphere_cases": lambda: math_figures.sphere_cases(),
    "math_plane_hit": lambda: math_figures.plane_hit(),
    "math_dot_projection": lambda: math_figures.dot_projection(),
    "linescan_slide_rays": lambda: ray_diagram(_linescan("slide")),
    "linescan_conveyor_rays": lambda: ray_diagram(_linescan("conveyor"), every=16),
    "linescan_car_sweep": lambda: sweep_diagram(_linescan("passing_car"), scans=375),
}


def draw(name: str, path: Path) -> None:
    figure = FIGURES[name]()
    try:
        figure.savefig(path, dpi=DPI)
    finally:
        plt.close(figure)


if __name__ == "__main__":
    FOLDER.mkdir(exist_ok=True)
    for name in sys.argv[1:] or FIGURES:
        draw(name, FOLDER / f"{name}.png")
        print(f"wrote {FOLDER / name}.png")

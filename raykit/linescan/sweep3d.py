"""The line-scan camera in 3D: a camera one pixel high, a scene in motion, one render a scan.

A road-monitoring camera looks across the road with a single row of pixels; its *plane of view*
is the plane through the eye that holds the row's rays. A car drives *through* that plane, and
each scan sees the slice of the car that is in the plane at that moment; the scans, side by
side, are a picture of the car. (In the 2D world of :mod:`raykit.linescan.scan` the plane of
view is the whole world, so a car can only move *within* it, sliding along the row: its sweep
shows bands, not a car.)

The camera is raykit's 3D camera (:mod:`raykit.camera`) with ``height`` 1: its pixels are the
points P_i = eye − d·w + s_i·u (the row's t is 0), which is the slide's p_i = e + x_i·u + D·w with
raykit's w pointing back (−w is the view direction) and everything scaled by d·tan(fov_h/2),
where fov_h is the row's own field of view. The camera's ``fov_angle`` is still the *vertical*
one, the angle of one square pixel: tan(fov_angle/2) = tan(fov_h/2) / width.

A sweep renders the scene at scans 0 .. M−1, scan m of :meth:`raykit.scene.Scene.at` (every
object moved by m·velocity), and sets the scans side by side: pixel i of scan m is image row i,
column m, so a camera whose u points down the world draws the car upright, the first scan at
the left.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from raykit.render import render
from raykit.scene import Scene


@dataclass(frozen=True)
class ColumnSweep:
    """M scans of N pixels side by side: ``image (N, M, 3)`` (column m is scan m) and
    ``index (N, M)``, the object each pixel's centre ray hit (-1 none)."""

    image: np.ndarray
    index: np.ndarray


def check_line_camera(scene: Scene) -> None:
    """Raise ValueError unless the scene's camera is one pixel high (a line-scan camera)."""
    if scene.camera.height != 1:
        raise ValueError(
            f"{scene.source}: camera.height: a line-scan sweep needs a camera one pixel high, "
            f"got {scene.camera.height}"
        )


def sweep_3d(
    scene: Scene,
    scans: int,
    samples: int = 1,
    progress: Callable[[int], None] | None = None,
    engine: str = "auto",
) -> ColumnSweep:
    """``scans`` renders of ``scene`` (camera one pixel high), scan m of ``scene.at(m)``.
    ``progress``, if given, is called with 1 as each scan is taken (a progress bar's update)."""
    check_line_camera(scene)
    if scans < 1:
        raise ValueError(f"scans must be >= 1, got {scans}")
    rows, indices = [], []
    for m in range(scans):
        taken = render(scene.at(m), samples, engine=engine)
        rows.append(taken.rgb[0])
        indices.append(taken.object_index[0])
        if progress is not None:
            progress(1)
    return ColumnSweep(
        image=np.stack(rows, axis=1),
        index=np.stack(indices, axis=1),
    )

"""Scans and sweeps: what the line-scan camera sees, once and over time.

* A **scan** is one row of N colours: pixel i takes the colour of what its ray hits first (the
  background where it hits nothing); with n samples per pixel, the mean of its n rays.
* A **sweep** is M scans, scan m taken after everything has moved by m·velocity
  (:meth:`raykit.linescan.scene.LineScene.at`), stacked into an (M, N) image, scan 0 on top.
  Something moving across the view is seen for about (its width) / (its speed) scans, so a
  slow car comes out stretched and a fast one squashed: the look of a photo-finish picture.

Pixel order and the camera conventions: :mod:`raykit.linescan.camera`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from raykit.hits import Hits, solid
from raykit.linescan.camera import line_rays
from raykit.linescan.objects import hit_ball, hit_segment, segment_color_at
from raykit.linescan.scene import LineScene
from raykit.rays import point_at


@dataclass(frozen=True)
class Scan:
    """One scan of N pixels: ``colors (N, 3)`` in [0, 1]; for the ray through each pixel
    centre, its ``origins (N, 2)``, unit ``directions (N, 2)``, the ``index (N,)`` of the
    object it hits (-1 none) and the hit's ``t (N,)`` (inf none)."""

    colors: np.ndarray
    index: np.ndarray
    t: np.ndarray
    origins: np.ndarray
    directions: np.ndarray

    @property
    def hit_points(self) -> np.ndarray:
        """Where each centre ray hits, ``(N, 2)``; NaN for a miss."""
        return point_at(self.origins, self.directions, self.t)


@dataclass(frozen=True)
class Sweep:
    """M scans stacked: ``image (M, N, 3)`` (row m is scan m) and ``index (M, N)``."""

    image: np.ndarray
    index: np.ndarray


def trace(scene: LineScene, origins: np.ndarray, directions: np.ndarray) -> Hits:
    """The nearest hit of each ray ``(N, 2)`` over the balls and billboards of the scene."""
    hits = Hits.none(len(origins), scene.background)
    for i, ball in enumerate(scene.balls):
        hits.keep_nearer(i, hit_ball(origins, directions, ball), solid(ball.color))
    for i, billboard in enumerate(scene.billboards, start=len(scene.balls)):
        t, s = hit_segment(origins, directions, billboard)
        hits.keep_nearer(i, t, segment_color_at(billboard, s))
    return hits


def scan(scene: LineScene, samples: int = 1) -> Scan:
    """One scan of ``scene`` with ``samples`` rays per pixel."""
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    pixels = scene.camera.pixels
    origins, directions = line_rays(scene.camera)
    centre = trace(scene, origins, directions)
    if samples == 1:
        colors = centre.color
    else:
        hits = trace(scene, *line_rays(scene.camera, samples))
        colors = hits.color.reshape(pixels, samples, 3).mean(axis=1)
    return Scan(colors, centre.index, centre.t, origins, directions)


def sweep(scene: LineScene, scans: int | None = None, samples: int = 1, progress=None) -> Sweep:
    """``scans`` scans (default: the scene's ``scans``), scan m of ``scene.at(m)``.
    ``progress``, if given, is called with 1 as each scan is taken (a progress bar's update)."""
    count = scene.scans if scans is None else scans
    if count < 1:
        raise ValueError(f"scans must be >= 1, got {count}")
    taken = []
    for m in range(count):
        taken.append(scan(scene.at(m), samples))
        if progress is not None:
            progress(1)
    return Sweep(
        image=np.stack([s.colors for s in taken]),
        index=np.stack([s.index for s in taken]),
    )

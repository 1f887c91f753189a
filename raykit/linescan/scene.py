"""A line-scan scene, as data: a 2D camera, balls and billboards, their motions.

Read from JSON by :mod:`raykit.io.linescan_json` (the format: ``docs/linescan-format.md``).
Geometry conventions: :mod:`raykit.linescan.camera` and :mod:`raykit.linescan.objects`.
Object indices: balls 0 .. B-1 in file order, then billboards, -1 for nothing; ties go to the
lower index.

Motion: the camera and every object may have a ``velocity``, in scene units per scan. Scan m of
a sweep sees everything moved by m·velocity (:meth:`LineScene.at`).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from raykit.linescan.camera import LineCamera
from raykit.linescan.objects import Ball, Billboard

DEFAULT_SCANS = 100


@dataclass(frozen=True)
class LineScene:
    """Everything a scan needs; ``camera_velocity (2,)`` moves the camera's e per scan."""

    camera: LineCamera
    balls: tuple[Ball, ...] = ()
    billboards: tuple[Billboard, ...] = ()
    background: np.ndarray = field(default_factory=lambda: np.zeros(3))
    camera_velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    scans: int = DEFAULT_SCANS
    source: str = "<scene>"

    @property
    def objects(self) -> tuple[Ball | Billboard, ...]:
        """All objects in index order: balls, then billboards."""
        return self.balls + self.billboards

    def at(self, scan: float) -> LineScene:
        """The scene as scan number ``scan`` sees it: everything moved by scan·velocity."""
        camera = replace(self.camera, e=self.camera.e + scan * self.camera_velocity)
        return replace(
            self,
            camera=camera,
            balls=tuple(b.moved(scan) for b in self.balls),
            billboards=tuple(b.moved(scan) for b in self.billboards),
        )

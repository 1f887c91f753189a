"""A scene's objects as the arrays the engine's skips work on, made once per render.

:class:`SceneArrays` holds what :class:`raykit.scene.Scene` (plain data) does not: the spheres'
centres, radii and colours stacked in object index order, and every object's padded bounding
box (:mod:`raykit.engine.boxes`), made on first use. The renderer makes it once
(:func:`SceneArrays.of`) and hands it to the tiles, the (object, ray) pairs, the BVH and the
culling of shadow rays.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from raykit.engine.boxes import object_boxes
from raykit.scene import Scene
from raykit.spheres import SphereTable


@dataclass(frozen=True)
class SceneArrays:
    """``centers (S, 3)``, ``radii (S,)``, ``sphere_colors (S, 3)`` of the spheres; ``boxes``:
    every object's box, ``lower`` and ``upper (K, 3)``, made when first asked for (a render of
    flat colours by the compiled engine never needs them); all in object index order."""

    centers: np.ndarray
    radii: np.ndarray
    sphere_colors: np.ndarray
    scene: Scene = field(repr=False)

    @classmethod
    def of(cls, scene: Scene) -> SceneArrays:
        spheres = scene.spheres
        if isinstance(spheres, SphereTable):  # the loader's columns, as they are
            return cls(spheres.centers, spheres.radii, spheres.colors, scene)
        if spheres:
            centers = np.stack([np.asarray(s.center) for s in spheres])
            radii = np.array([s.radius for s in spheres])
        else:
            centers, radii = np.zeros((0, 3)), np.zeros(0)
        colors = np.array([s.color for s in spheres], dtype=float).reshape(-1, 3)
        return cls(centers, radii, colors, scene)

    @cached_property
    def boxes(self) -> tuple[np.ndarray, np.ndarray]:
        return object_boxes(self.centers, self.radii, self.scene.billboards)

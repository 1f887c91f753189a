"""Lights, and the unit vector l from a surface point toward each one (FOCG 4.5).

Conventions (shared by :mod:`raykit.shading`, :mod:`raykit.shadows` and :mod:`raykit.mirrors`)
---------------------------------------------------------------------------------------------
* Every vector of the shading formulas is unit length and points *away* from the surface
  point p: l toward the light, v toward the viewer (v = -d), n the surface normal, h the
  half vector, r the mirror direction.
* A directional light (the sun) shines along ``direction``: the way its light *travels*, from
  the light into the scene. So l = -direction / |direction|, the same at every point, and the
  light is infinitely far away.
* A point light sits at ``position``: l = (position - p) / |position - p|, and the light is
  |position - p| away. Its intensity does not fall off with distance (as in FOCG 4.5; a
  physically based renderer would divide by the distance squared).
* A light's ``color`` is its intensity I per channel, >= 0; it may exceed 1 for a bright light.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from raykit.rays import dot, normalize

LIGHT_TYPES = ("directional", "point")


@dataclass(frozen=True)
class DirectionalLight:
    """Light from infinitely far away, travelling along ``direction (3,)``; ``color (3,)``."""

    direction: np.ndarray
    color: np.ndarray


@dataclass(frozen=True)
class PointLight:
    """Light from ``position (3,)`` in every direction; ``color (3,)``."""

    position: np.ndarray
    color: np.ndarray


Light = DirectionalLight | PointLight


def toward_light(light: Light, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors l ``(N, 3)`` from surface points ``(N, 3)`` to the light, and the distance
    to it ``(N,)`` (inf for a directional light): a shadow ray's blocker counts only if nearer."""
    # BEGIN SOLUTION
    # hint: directional: l = -direction (normalised), distance inf; point: l = position - p,
    #       normalised, distance |position - p|
    if isinstance(light, DirectionalLight):
        l = np.broadcast_to(normalize(-np.asarray(light.direction, float)), points.shape)
        return l, np.full(len(points), np.inf)
    to_light = np.asarray(light.position) - points
    distance = np.sqrt(dot(to_light, to_light))
    return to_light / distance[:, None], distance
    # END SOLUTION

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
* An area light (stage 5, FOCG 13.4.2) is a parallelogram, like a billboard: the points
  c + ξ1·a + ξ2·b, ξ1, ξ2 in [0, 1], of its ``corner`` c and edges ``edge1`` a and ``edge2`` b
  (:func:`raykit.sampling.point_on_parallelogram`). It is *sampled*: each shading point aims its
  shadow ray at its own point of the light (:func:`sampled`), and from there the light is a point
  light of the same colour, so a soft shadow is the mean over many samples, and a light shrunk
  to a point is the point light. Like the point light it neither falls off with distance nor
  depends on the angle at which it is seen (FOCG's simple model; a physically based renderer
  divides by the distance squared and weighs by the cosine at the light).
* A light's ``color`` is its intensity I per channel, >= 0; it may exceed 1 for a bright light.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from raykit.rays import dot, normalize
from raykit.sampling import point_on_parallelogram

LIGHT_TYPES = ("directional", "point", "area")


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


@dataclass(frozen=True)
class AreaLight:
    """Light from the parallelogram ``corner`` + ξ1·``edge1`` + ξ2·``edge2`` (each ``(3,)``),
    sampled a point per shadow ray; ``color (3,)``."""

    corner: np.ndarray
    edge1: np.ndarray
    edge2: np.ndarray
    color: np.ndarray


Light = DirectionalLight | PointLight | AreaLight


def sampled(light: AreaLight, uniforms: np.ndarray) -> PointLight:
    """The area light as point lights, one per shading point: positions ``(N, 3)`` on it from
    ``uniforms (N, 2)`` (:func:`raykit.sampling.point_on_parallelogram`), the same colour. A
    stage-5 student function."""
    # BEGIN SOLUTION
    # hint: a PointLight whose position (N, 3) is the point of the parallelogram each row of
    #       uniforms chooses (point_on_parallelogram), with the light's colour
    return PointLight(
        point_on_parallelogram(light.corner, light.edge1, light.edge2, uniforms), light.color
    )
    # END SOLUTION


def toward_light(light: Light, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors l ``(N, 3)`` from surface points ``(N, 3)`` to the light, and the distance
    to it ``(N,)`` (inf for a directional light): a shadow ray's blocker counts only if nearer.
    A point light's ``position`` may be ``(N, 3)``, one per point (an area light,
    :func:`sampled`)."""
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

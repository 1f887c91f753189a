"""Shadows (FOCG 4.7): a point is in shadow from a light when something lies between them.

From a surface point p, a *shadow ray* goes toward the light, along l
(:func:`raykit.lights.toward_light`). The light is blocked if the ray's nearest hit is nearer
than the light: t < |light - p| for a point light, any hit at all for a directional light.
A billboard's transparent texels (holes) let light through, as they let the eye see through.

The ray starts a little off the surface (:meth:`raykit.surfaces.SurfacePoints.start`), or it may
hit the very surface it starts on and shade the point wrongly ("shadow acne").

Only points that face the light (n·l > 0) need a shadow ray: the others receive no direct light
anyway, whatever lies in between (:func:`raykit.shading.shade` asks only about those).

How far the light is (:func:`light_reach`). The shadow ray is the segment from p to the light
shortened by the offset at *both* ends: it starts at o' = p + ε·n, and the light's distance is
measured from o' and shortened by ε' = OFFSET_FACTOR·eps·(max|o'| + |q - o'|), the rounding
bound of a point that far along the ray. A blocker counts when the shadow ray meets it at
t < |q - o'| - ε'. So a surface the light lies on (a lamp on a wall) never shadows it, where
the rule "t < |q - p|" decided it by rounding and speckled the floor; anything farther from the
light than ε' still does.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from raykit.hits import Hits
from raykit.lights import DirectionalLight, Light
from raykit.rays import dot
from raykit.surfaces import OFFSET_FACTOR, SurfacePoints

# (origins (N, 3), unit directions (N, 3), optionally t_max (N,)) -> the nearest hits over the
# whole scene; with t_max, hits at t >= t_max may be reported as misses (only nearer ones matter)
Caster = Callable[..., Hits]


def in_shadow(
    cast: Caster, surface: SurfacePoints, l: np.ndarray, distance: np.ndarray
) -> np.ndarray:
    """``(N,)`` bool: is something between each surface point and its light?

    ``cast``: the scene's nearest-hit function, ``cast(origins, directions, t_max)``; hits beyond
    ``t_max`` do not matter to it, so it may skip objects beyond the light. ``l (N, 3)``: unit
    vectors toward the light; ``distance (N,)``: how far the light is (inf for a directional
    light).
    """
    # BEGIN SOLUTION
    # hint: cast shadow rays from surface.start(l) (the points lifted off their surface) along
    #       l, up to the light's distance; in shadow where the nearest hit is nearer than the light
    hits = cast(surface.start(l), l, distance)
    return hits.t < distance
    # END SOLUTION


def light_reach(surface: SurfacePoints, l: np.ndarray, light: Light) -> np.ndarray:
    """``(N,)``: how far a shadow ray from each surface point may go along ``l (N, 3)`` before
    a hit no longer blocks ``light``: the distance from the ray's start (the offset point) to
    the light, less the offset's margin at the light's end (see the module page); inf for a
    directional light."""
    if isinstance(light, DirectionalLight):
        return np.full(len(l), np.inf)
    start = surface.start(l)
    to_light = np.asarray(light.position) - start
    distance = np.sqrt(dot(to_light, to_light))
    eps = np.finfo(start.dtype).eps
    return distance - OFFSET_FACTOR * eps * (np.abs(start).max(axis=1) + distance)

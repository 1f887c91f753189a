"""Repeats :mod:`raykit.lights` for one point: the unit vector l toward a point light."""

from __future__ import annotations

import math

from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY


@njit(**ONE_RAY)
def toward_point_light(v0, v1, v2, p0, p1, p2):
    """Repeats :func:`raykit.lights.toward_light` for a point light at v: the unit l from p."""
    to0, to1, to2 = v0 - p0, v1 - p1, v2 - p2
    distance = math.sqrt(to0 * to0 + to1 * to1 + to2 * to2)
    return to0 / distance, to1 / distance, to2 / distance

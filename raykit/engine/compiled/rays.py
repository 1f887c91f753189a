"""Repeats :mod:`raykit.rays` for one ray: the ray itself, and the nearer positive root."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY


class Ray(NamedTuple):
    """One ray p(t) = o + t·d (:mod:`raykit.rays`): its origin (``o0``, ``o1``, ``o2``) and
    direction (``d0``, ``d1``, ``d2``), as plain floats that the kernels keep in registers."""

    o0: float
    o1: float
    o2: float
    d0: float
    d1: float
    d2: float


@njit(**ONE_RAY)
def nearest_positive(t0: float, t1: float) -> float:
    """Repeats :func:`raykit.rays.nearest_positive` for one ray (np.fmin/np.fmax ignore a NaN
    partner, as here)."""
    if math.isnan(t0):
        t_near = t1
        t_far = t1
    elif math.isnan(t1):
        t_near = t0
        t_far = t0
    else:
        t_near = min(t0, t1)
        t_far = max(t0, t1)
    if t_near > 0:
        return t_near
    if t_far > 0:
        return t_far
    return np.inf

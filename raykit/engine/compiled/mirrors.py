"""Repeats :mod:`raykit.mirrors` for one ray: its mirror direction. (The bounces themselves
are :func:`raykit.shading.shade`'s loop, and so
:mod:`raykit.engine.compiled.shading`'s.)"""

from __future__ import annotations

from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY


@njit(**ONE_RAY)
def reflect(d0, d1, d2, n0, n1, n2):
    """Repeats :func:`raykit.mirrors.reflect` for one ray: r = d - 2(d·n)n."""
    twice = 2.0 * (d0 * n0 + d1 * n1 + d2 * n2)
    return d0 - twice * n0, d1 - twice * n1, d2 - twice * n2

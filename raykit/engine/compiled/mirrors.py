"""Repeats :mod:`raykit.mirrors` for one ray: its mirror direction, and a glossy mirror's
perturbed one. (The bounces themselves are :func:`raykit.shading.shade`'s loop, and so
:mod:`raykit.engine.compiled.shading`'s.)"""

from __future__ import annotations

from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY
from raykit.engine.compiled.sampling import perturbed_direction


@njit(**ONE_RAY)
def reflect(d0, d1, d2, n0, n1, n2):
    """Repeats :func:`raykit.mirrors.reflect` for one ray: r = d - 2(d·n)n."""
    twice = 2.0 * (d0 * n0 + d1 * n1 + d2 * n2)
    return d0 - twice * n0, d1 - twice * n1, d2 - twice * n2


@njit(**ONE_RAY)
def sign(x):
    """np.sign of one number: -1, 0 or 1 (0 for either zero), NaN for NaN."""
    if x > 0:
        return 1.0
    if x < 0:
        return -1.0
    return x * 0.0  # 0 for a zero, NaN for NaN


@njit(**ONE_RAY)
def glossy_reflect(d0, d1, d2, n0, n1, n2, a, x1, x2):
    """Repeats :func:`raykit.mirrors.glossy_reflect` for one ray of glossiness ``a`` and its
    uniform numbers (ξ1, ξ2): ``(r'0, r'1, r'2, above)``, the mirror direction perturbed
    (:func:`raykit.engine.compiled.sampling.perturbed_direction`; a = 0: r itself) and whether
    it leaves above the surface, on the side d came from."""
    r0, r1, r2 = reflect(d0, d1, d2, n0, n1, n2)
    if not a > 0:
        return r0, r1, r2, True
    p0, p1, p2 = perturbed_direction(r0, r1, r2, a, x1, x2)
    above = sign(p0 * n0 + p1 * n1 + p2 * n2) == -sign(d0 * n0 + d1 * n1 + d2 * n2)
    return p0, p1, p2, above

"""The mirror direction and a glossy mirror's (raykit.engine.compiled.mirrors) against
raykit.mirrors.reflect and glossy_reflect."""

from __future__ import annotations

import numba
import numpy as np

from raykit.engine.compiled import mirrors as kernels
from raykit.mirrors import glossy_reflect, reflect
from raykit.rays import normalize

from .harness import exactly, twin_test


def _reflect(rng):
    d, n = normalize(rng.normal(size=(2, 4000, 3)))
    got = [kernels.reflect(*d[i], *n[i]) for i in range(len(d))]
    exactly(got, reflect(d, n))


@numba.njit
def _glossy(d, n, a, xi):
    out = np.empty((len(d), 4))
    for i in range(len(d)):
        out[i, 0], out[i, 1], out[i, 2], above = kernels.glossy_reflect(
            d[i, 0], d[i, 1], d[i, 2], n[i, 0], n[i, 1], n[i, 2], a[i], xi[i, 0], xi[i, 1]
        )
        out[i, 3] = above
    return out


def _glossy_reflect(rng):
    count = 20_000
    d, n = normalize(rng.normal(size=(2, count, 3)))
    n[:50] = np.eye(3)[rng.integers(0, 3, 50)]  # normals along an axis: the basis's ties
    a = rng.choice([0.0, 0.05, 0.3, 1.0, 2.5], size=count)  # 0: the ideal mirror
    xi = rng.uniform(size=(count, 2))
    r_prime, above = glossy_reflect(d, n, a, xi)
    got = _glossy(d, n, a, xi)
    exactly(got[:, :3], r_prime)
    assert np.array_equal(got[:, 3].astype(bool), above)
    assert 0.01 < (~above).mean() < 0.5  # some absorbed, by the wide squares


CHECKS = {"mirrors.reflect": _reflect, "mirrors.glossy_reflect": _glossy_reflect}
test_the_twin_repeats_its_reference = twin_test("mirrors", CHECKS)

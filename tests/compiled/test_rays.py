"""The nearer positive root (raykit.engine.compiled.rays) against raykit.rays."""

from __future__ import annotations

import numpy as np

from raykit.engine.compiled import rays as kernels
from raykit.rays import nearest_positive

from .harness import exactly, twin_test


def _nearest_positive(rng):
    t0, t1 = rng.normal(size=(2, 4000)) * 5
    t0[::7], t1[::11], t0[::13], t1[::17], t0[::19] = np.nan, np.nan, np.inf, -np.inf, 0.0
    got = [kernels.nearest_positive(a, b) for a, b in zip(t0, t1, strict=True)]
    exactly(got, nearest_positive(t0, t1))


CHECKS = {"rays.nearest_positive": _nearest_positive}
test_the_twin_repeats_its_reference = twin_test("rays", CHECKS)

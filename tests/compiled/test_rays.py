"""The nearer positive root (raykit.engine.compiled.rays) against raykit.rays."""

from __future__ import annotations

import numpy as np
import pytest

from .harness import exactly, twin_test

numba = pytest.importorskip("numba")
compiled = pytest.importorskip("raykit.engine.compiled")

from raykit.engine.compiled import rays as kernels  # noqa: E402
from raykit.rays import nearest_positive  # noqa: E402


def _nearest_positive(rng):
    t0, t1 = rng.normal(size=(2, 4000)) * 5
    t0[::7], t1[::11], t0[::13], t1[::17], t0[::19] = np.nan, np.nan, np.inf, -np.inf, 0.0
    got = [kernels.nearest_positive(a, b) for a, b in zip(t0, t1, strict=True)]
    exactly(got, nearest_positive(t0, t1))


CHECKS = {"rays.nearest_positive": _nearest_positive}
test_the_twin_repeats_its_reference = twin_test("rays", CHECKS)

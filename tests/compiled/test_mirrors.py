"""The mirror direction (raykit.engine.compiled.mirrors) against raykit.mirrors.reflect."""

from __future__ import annotations

import pytest

from .harness import exactly, twin_test

numba = pytest.importorskip("numba")
compiled = pytest.importorskip("raykit.engine.compiled")

from raykit.engine.compiled import mirrors as kernels  # noqa: E402
from raykit.mirrors import reflect  # noqa: E402
from raykit.rays import normalize  # noqa: E402


def _reflect(rng):
    d, n = normalize(rng.normal(size=(2, 4000, 3)))
    got = [kernels.reflect(*d[i], *n[i]) for i in range(len(d))]
    exactly(got, reflect(d, n))


CHECKS = {"mirrors.reflect": _reflect}
test_the_twin_repeats_its_reference = twin_test("mirrors", CHECKS)

"""The unit vector toward a point light (raykit.engine.compiled.lights) against
raykit.lights.toward_light."""

from __future__ import annotations

import numpy as np
import pytest

from .harness import exactly, twin_test

numba = pytest.importorskip("numba")
compiled = pytest.importorskip("raykit.engine.compiled")

from raykit.engine.compiled import lights as kernels  # noqa: E402
from raykit.lights import PointLight, toward_light  # noqa: E402


def _toward_point_light(rng):
    position = rng.normal(size=3) * 5
    points = rng.normal(size=(4000, 3)) * 5
    expected, _ = toward_light(PointLight(position, np.ones(3)), points)
    got = [kernels.toward_point_light(*position, *p) for p in points]
    exactly(got, expected)


CHECKS = {"lights.toward_point_light": _toward_point_light}
test_the_twin_repeats_its_reference = twin_test("lights", CHECKS)

"""How far a shadow ray's blocker counts (raykit.engine.compiled.shadows) against
raykit.shadows.light_reach. (The shadow lists are the compiled engine's own: their answers are
checked through whole renders, tests/compiled/test_shading.py.)"""

from __future__ import annotations

import numpy as np

from raykit.engine.compiled import shadows as kernels
from raykit.lights import PointLight
from raykit.rays import normalize
from raykit.shadows import light_reach
from raykit.surfaces import SurfacePoints

from .harness import exactly, twin_test


def _point_light_reach(rng):
    count = 4000
    points = rng.normal(size=(count, 3)) * 10.0 ** rng.integers(-1, 7, size=(count, 1))
    normals = normalize(rng.normal(size=(count, 3)))
    surface = SurfacePoints(points, normals, rng.uniform(0, 1e-12, size=count))
    position = rng.normal(size=3) * 20
    light = PointLight(position, np.ones(3))
    l = normalize(position - points)  # FOCG's l, toward the light
    expected = light_reach(surface, l, light)
    starts = surface.start(l)
    got = [kernels.point_light_reach(*position, *s) for s in starts]
    exactly(got, expected)


CHECKS = {"shadows.point_light_reach": _point_light_reach}
test_the_twin_repeats_its_reference = twin_test("shadows", CHECKS)

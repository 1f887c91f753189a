"""The unit vector toward a point light, and an area light's sampled points
(raykit.engine.compiled.lights), against raykit.lights.toward_light and sampled."""

from __future__ import annotations

import numba
import numpy as np

from raykit.engine import compiled
from raykit.engine.compiled import lights as kernels
from raykit.lights import AreaLight, PointLight, sampled, toward_light
from raykit.scene import Scene

from .harness import exactly, twin_test
from .test_camera import _pinhole


def _toward_point_light(rng):
    position = rng.normal(size=3) * 5
    points = rng.normal(size=(4000, 3)) * 5
    expected, _ = toward_light(PointLight(position, np.ones(3)), points)
    got = [kernels.toward_point_light(*position, *p) for p in points]
    exactly(got, expected)


@numba.njit
def _sampled_points(shading, j, xi):
    out = np.empty((len(xi), 3))
    for i in range(len(xi)):
        out[i, 0], out[i, 1], out[i, 2] = kernels.sampled(shading, j, xi[i, 0], xi[i, 1])
    return out


def _sampled(rng):
    lights = [
        AreaLight(*(rng.normal(size=(3, 3)) * scale), np.ones(3)) for scale in (1.0, 5.0, 1e6)
    ]
    point = PointLight(rng.normal(size=3), np.ones(3))
    shading = compiled.scene_shading(Scene(_pinhole(), lights=(lights[0], point, *lights[1:])))
    xi = rng.uniform(size=(4000, 2))
    for j, light in zip((0, 2, 3), lights, strict=True):
        exactly(_sampled_points(shading, j, xi), sampled(light, xi).position)


CHECKS = {"lights.toward_point_light": _toward_point_light, "lights.sampled": _sampled}
test_the_twin_repeats_its_reference = twin_test("lights", CHECKS)

"""The unit vector toward a point light, an area light's sampled points and the intensity they
send (raykit.engine.compiled.lights), against raykit.lights.toward_light, sampled and
area_intensity."""

from __future__ import annotations

import numba
import numpy as np

from raykit.engine import compiled
from raykit.engine.compiled import lights as kernels
from raykit.lights import AreaLight, PointLight, area_intensity, sampled, toward_light
from raykit.scene import Scene

from .harness import exactly, twin_test
from .test_camera import _pinhole


def _toward_point_light(rng):
    position = rng.normal(size=3) * 5
    points = rng.normal(size=(4000, 3)) * 5
    expected, distance = toward_light(PointLight(position, np.ones(3)), points)
    got = np.array([kernels.toward_point_light(*position, *p) for p in points])
    exactly(got[:, :3], expected)
    exactly(got[:, 3], distance)


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


@numba.njit
def _intensities(shading, j, l, distance):
    out = np.empty((len(l), 3))
    for i in range(len(l)):
        out[i, 0], out[i, 1], out[i, 2] = kernels.area_intensity(
            kernels.area_light(shading, j), l[i, 0], l[i, 1], l[i, 2], distance[i]
        )
    return out


def _area_intensity(rng):
    """FOCG's light and physically based ones (near, far, huge), toward random points, some
    behind the light."""
    lights = [
        AreaLight(*(rng.normal(size=(3, 3)) * scale), rng.uniform(size=3) * 4, physical=physical)
        for scale, physical in ((1.0, False), (1.0, True), (5.0, True), (1e6, True))
    ]
    shading = compiled.scene_shading(Scene(_pinhole(), lights=tuple(lights)))
    points = rng.normal(size=(4000, 3)) * 5
    for j, light in enumerate(lights):
        l, distance = toward_light(sampled(light, rng.uniform(size=(4000, 2))), points)
        expected = area_intensity(light, l, distance)
        exactly(_intensities(shading, j, np.ascontiguousarray(l), distance), expected)
        if j == 1:  # a physically based light among the points: seen from both its sides
            assert (expected == 0).any() and (expected > 0).any()


CHECKS = {
    "lights.toward_point_light": _toward_point_light,
    "lights.sampled": _sampled,
    "lights.area_intensity": _area_intensity,
    "lights.area_light": _area_intensity,
}
test_the_twin_repeats_its_reference = twin_test("lights", CHECKS)

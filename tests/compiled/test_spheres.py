"""The sphere kernel (raykit.engine.compiled.spheres) against raykit.spheres, bit for bit on random
rays and the stability cases."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from raykit.engine import compiled
from raykit.spheres import center_at, hit_sphere

from .harness import (
    RAYS,
    exactly,
    random_rays,
    twin_test,
)


@numba.njit
def _spheres(origins, directions, centers, radii):
    t = np.empty(len(origins))
    for i in range(len(origins)):
        o, d, c = origins[i], directions[i], centers[i]
        t[i] = compiled.hit_sphere(o[0], o[1], o[2], d[0], d[1], d[2], c[0], c[1], c[2], radii[i])
    return t


def test_sphere_kernel_repeats_hit_sphere_bit_for_bit_on_random_rays():
    rng = np.random.default_rng(18)
    origins, directions = random_rays(rng, RAYS)
    aim = rng.uniform(0, 30, size=(RAYS, 1)) * directions  # half the rays pass near a centre
    centers = origins + aim + rng.normal(size=(RAYS, 3)) * rng.uniform(0, 3, size=(RAYS, 1))
    radii = rng.uniform(0.01, 4, size=RAYS)
    expected = hit_sphere(origins, directions, centers, radii)
    assert 0.2 < np.isfinite(expected).mean() < 0.9  # hits and misses both tested
    exactly(_spheres(origins, directions, centers, radii), expected)


@pytest.mark.parametrize(
    "case",
    ["far_tiny", "grazing", "from_the_surface", "inside", "at_1e6", "unnormalised", "tie"],
)
def test_sphere_kernel_agrees_on_the_stability_cases(case):
    rng = np.random.default_rng(4)
    count = 20_000
    origins, directions = random_rays(rng, count, 1.0)
    radii = np.full(count, 1.0)
    centers = origins + 5 * directions + rng.normal(size=(count, 3)) * 0.3
    if case == "far_tiny":  # a radius 1e-3 ball 1e5 away
        radii[:] = 1e-3
        centers = origins + 1e5 * directions + rng.normal(size=(count, 3)) * 1e-3
    elif case == "grazing":  # the line passes at exactly (to rounding) the radius
        side = np.cross(directions, rng.normal(size=(count, 3)))
        side /= np.linalg.norm(side, axis=1, keepdims=True)
        centers = origins + 5 * directions + side * radii[:, None]
    elif case == "from_the_surface":  # rays that start on the sphere, inwards and outwards
        normal = rng.normal(size=(count, 3))
        normal /= np.linalg.norm(normal, axis=1, keepdims=True)
        centers = origins - normal
    elif case == "inside":
        centers = origins + rng.normal(size=(count, 3)) * 0.1
    elif case == "at_1e6":
        origins, centers = origins + 1e6, centers + 1e6
    elif case == "unnormalised":
        directions = directions * rng.uniform(1e-3, 1e3, size=(count, 1))
    elif case == "tie":  # rays along an axis, through the centre: both roots exact
        directions = np.tile([0.0, 0.0, 1.0], (count, 1))
        centers = origins + [0.0, 0.0, 3.0]
    expected = hit_sphere(origins, directions, centers, radii)
    exactly(_spheres(origins, directions, centers, radii), expected)


def _hit_sphere(rng):
    origins, directions = random_rays(rng, 20_000)
    aim = rng.uniform(0, 30, size=(len(origins), 1)) * directions
    centers = (
        origins + aim + rng.normal(size=origins.shape) * rng.uniform(0, 3, size=(len(origins), 1))
    )
    radii = rng.uniform(0.01, 4, size=len(origins))
    exactly(
        _spheres(origins, directions, centers, radii),
        hit_sphere(origins, directions, centers, radii),
    )


def _center_at(rng):
    count = 20_000
    times = rng.uniform(0, 2, size=count)
    times[:3] = 0.0, 1.0, np.nextafter(1.0, 0.0)
    for scale in (1.0, 1e6):
        center, velocity = rng.normal(size=(2, 3)) * scale

        @numba.njit
        def run(center, velocity, times):
            out = np.empty((len(times), 3))
            for i in range(len(times)):
                out[i, 0], out[i, 1], out[i, 2] = compiled.spheres.center_at(
                    center[0], center[1], center[2], velocity[0], velocity[1], velocity[2],
                    times[i],
                )  # fmt: skip
            return out

        exactly(run(center, velocity, times), center_at(center, velocity, times))


CHECKS = {"spheres.hit_sphere": _hit_sphere, "spheres.center_at": _center_at}
test_the_twin_repeats_its_reference = twin_test("spheres", CHECKS)

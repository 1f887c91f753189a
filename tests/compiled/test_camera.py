"""The viewing-ray kernels (raykit.engine.compiled.camera) against raykit.camera.rays_through
and thin_lens_rays."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from raykit.camera import Camera, rays_through, thin_lens_rays
from raykit.engine import compiled
from raykit.scene import Scene

from .harness import (
    RAYS,
    exactly,
    twin_test,
)


@numba.njit
def _viewing_rays(camera, x, y):
    out = np.empty((len(x), 6))
    for i in range(len(x)):
        ray = compiled.rays_through(camera, x[i], y[i])
        out[i] = ray.o0, ray.o1, ray.o2, ray.d0, ray.d1, ray.d2
    return out


@pytest.mark.parametrize("projection", ["perspective", "orthographic"])
@pytest.mark.parametrize("far", [False, True])
def test_viewing_ray_kernel_repeats_rays_through(projection, far):
    rng = np.random.default_rng(11)
    for _ in range(5):
        eye = rng.normal(size=3) * (1e6 if far else 5)
        camera = Camera(
            eye, eye + rng.normal(size=3), rng.normal(size=3), rng.uniform(5, 120),
            int(rng.integers(1, 400)), int(rng.integers(1, 400)), projection,
        )  # fmt: skip
        x = rng.uniform(0, camera.width, size=RAYS // 5)
        y = rng.uniform(0, camera.height, size=RAYS // 5)
        origins, directions = rays_through(camera, x, y)
        scene = Scene(camera)
        got = _viewing_rays(compiled.camera_tuple(scene), x, y)
        exactly(got[:, :3], origins)
        exactly(got[:, 3:], directions)


def _rays_through(rng):
    for projection in ("perspective", "orthographic"):
        eye = rng.normal(size=3) * 5
        camera = Camera(eye, eye + rng.normal(size=3), rng.normal(size=3), rng.uniform(5, 120),
                        64, 48, projection)  # fmt: skip
        x, y = rng.uniform(0, 64, size=4000), rng.uniform(0, 48, size=4000)
        origins, directions = rays_through(camera, x, y)
        got = _viewing_rays(compiled.camera_tuple(Scene(camera)), x, y)
        exactly(got, np.concatenate([origins, directions], axis=1))


def _pinhole(eye=(0.0, 0.0, 0.0), **lens):
    eye = np.asarray(eye, float)
    return Camera(eye, eye + np.array([0.3, -0.2, -1.0]), np.array([0.0, 1.0, 0.0]), 50, 64, 48,
                  **lens)  # fmt: skip


@numba.njit
def _lens_rays(camera, lens, x, y, xi):
    out = np.empty((len(x), 6))
    for i in range(len(x)):
        ray = compiled.thin_lens_rays(camera, lens, x[i], y[i], xi[i, 0], xi[i, 1])
        out[i] = ray.o0, ray.o1, ray.o2, ray.d0, ray.d1, ray.d2
    return out


def _thin_lens_rays(rng):
    for eye, aperture, focus in ((0.0, 0.5, None), (5.0, 0.05, 3.7), (1e6, 2.0, 40.0)):
        camera = _pinhole(rng.normal(size=3) * eye, aperture=aperture, focus_distance=focus)
        scene = Scene(camera)
        x, y = rng.uniform(0, 64, size=4000), rng.uniform(0, 48, size=4000)
        xi = rng.uniform(size=(4000, 2))
        xi[:3] = (0.5, 0.5), (0.0, 0.0), (0.5, 0.0)  # the lens's centre and edges
        origins, directions = thin_lens_rays(camera, x, y, xi)
        got = _lens_rays(compiled.camera_tuple(scene), compiled.lens_tuple(scene), x, y, xi)
        exactly(got, np.concatenate([origins, directions], axis=1))


CHECKS = {"camera.rays_through": _rays_through, "camera.thin_lens_rays": _thin_lens_rays}
test_the_twin_repeats_its_reference = twin_test("camera", CHECKS)

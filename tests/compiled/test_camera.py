"""The viewing-ray kernel (raykit.engine.compiled.camera) against raykit.camera.rays_through."""

from __future__ import annotations

import numpy as np
import pytest

from raykit.camera import Camera, rays_through
from raykit.scene import Scene

from .harness import (
    RAYS,
    exactly,
    twin_test,
)

numba = pytest.importorskip("numba")
compiled = pytest.importorskip("raykit.engine.compiled")


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


CHECKS = {"camera.rays_through": _rays_through}
test_the_twin_repeats_its_reference = twin_test("camera", CHECKS)

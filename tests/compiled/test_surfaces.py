"""A hit's surface point and where a ray leaving it starts (raykit.engine.compiled.surfaces),
against raykit.surfaces."""

from __future__ import annotations

import numpy as np

from raykit.engine import compiled
from raykit.engine.compiled import surfaces as kernels
from raykit.render import cast
from raykit.surfaces import SurfacePoints, surface_points

from .harness import exactly, lit_crowd, rays_into_crowd, twin_test


def _surface_points(rng):
    scene = lit_crowd(rng, 30)
    origins, directions = rays_into_crowd(rng, 4000)
    hits = cast(scene, origins, directions)
    hit = np.flatnonzero(hits.index >= 0)
    o, d, t, index = origins[hit], directions[hit], hits.t[hit], hits.index[hit]
    expected = surface_points(scene, o, d, t, index)
    arrays, shading = compiled.scene_arrays(scene), compiled.scene_shading(scene)
    got = np.array([kernels.surface_points(arrays, shading, *o[i], *d[i], index[i], t[i])
                    for i in range(len(hit))])  # fmt: skip
    assert len(hit) > 500 and (index >= len(scene.spheres)).any()  # billboards too
    exactly(got[:, :3], expected.points)
    exactly(got[:, 3:6], expected.normals)
    exactly(got[:, 6], expected.error)


def _start(rng):
    count = 4000
    points = rng.normal(size=(count, 3)) * 10.0 ** rng.integers(-2, 7, size=(count, 1))
    normals = rng.normal(size=(count, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    error = rng.uniform(0, 1e-12, size=count)
    directions = rng.normal(size=(count, 3))  # leaving on either side
    expected = SurfacePoints(points, normals, error).start(directions)
    got = [kernels.start(*points[i], *normals[i], error[i], *directions[i]) for i in range(count)]
    exactly(got, expected)


CHECKS = {"surfaces.surface_points": _surface_points, "surfaces.start": _start}
test_the_twin_repeats_its_reference = twin_test("surfaces", CHECKS)

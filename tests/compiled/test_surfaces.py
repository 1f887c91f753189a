"""A hit's surface point and where a ray leaving it starts (raykit.engine.compiled.surfaces),
against raykit.surfaces."""

from __future__ import annotations

import numpy as np

from raykit.engine import compiled
from raykit.engine.compiled import surfaces as kernels
from raykit.render import cast
from raykit.surfaces import SurfacePoints, surface_points

from .harness import exactly, lit_crowd, rays_into_crowd, twin_test


def _crowd_hits(rng):
    """Rays' hits on a crowd of 30 objects, billboards among them: the scene's arrays and
    shading, the rays' o, d, t and object index, and the reference's surface points."""
    scene = lit_crowd(rng, 30)
    origins, directions = rays_into_crowd(rng, 4000)
    hits = cast(scene, origins, directions)
    hit = np.flatnonzero(hits.index >= 0)
    o, d, t, index = origins[hit], directions[hit], hits.t[hit], hits.index[hit]
    assert len(hit) > 500 and (index >= len(scene.spheres)).any()  # billboards too
    expected = surface_points(scene, o, d, t, index)
    arrays, shading = compiled.scene_arrays(scene), compiled.scene_shading(scene)
    return arrays, shading, o, d, t, index, expected


def _same_points(got, expected):
    exactly(got[:, :3], expected.points)
    exactly(got[:, 3:6], expected.normals)
    exactly(got[:, 6], expected.error)


def _surface_points(rng):
    arrays, shading, o, d, t, index, expected = _crowd_hits(rng)
    got = np.array([kernels.surface_points(arrays, shading, *o[i], *d[i], index[i], t[i])
                    for i in range(len(o))])  # fmt: skip
    _same_points(got, expected)


def _point_and_normal(rng):
    """From each hit's object's numbers (hit_object), with no branch."""
    arrays, shading, o, d, t, index, expected = _crowd_hits(rng)
    got = np.array([
        kernels.point_and_normal(*o[i], *d[i], t[i], *kernels.hit_object(arrays, shading, index[i]))
        for i in range(len(o))
    ])  # fmt: skip
    _same_points(got, expected)


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


CHECKS = {
    "surfaces.surface_points": _surface_points,
    "surfaces.point_and_normal": _point_and_normal,
    "surfaces.start": _start,
}
test_the_twin_repeats_its_reference = twin_test("surfaces", CHECKS)

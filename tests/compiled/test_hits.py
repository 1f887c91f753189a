"""The nearest hit so far, offered one object more (raykit.engine.compiled.hits), against
raykit.hits.Hits.keep_nearer, as raykit.render.cast offers every object in index order."""

from __future__ import annotations

import numba
import numpy as np

from raykit.engine import compiled
from raykit.engine.compiled import hits as kernels
from raykit.engine.compiled.rays import Ray
from raykit.render import cast

from .harness import crowd, exactly, rays_into_crowd, twin_test


@numba.njit
def _offer_all(arrays, objects, origins, directions):
    out = np.empty((len(origins), 5))
    background = arrays.background
    for i in range(len(origins)):
        o, d = origins[i], directions[i]
        ray = Ray(o0=o[0], o1=o[1], o2=o[2], d0=d[0], d1=d[1], d2=d[2])
        hit = kernels.NearestHit(index=np.int64(-1), t=np.inf, r=background[0],
                                 g=background[1], b=background[2])  # fmt: skip
        for obj in range(objects):
            hit = kernels.keep_nearer(arrays, obj, ray, hit)
        out[i, 0], out[i, 1], out[i, 2], out[i, 3], out[i, 4] = hit
    return out


def _keep_nearer(rng):
    scene = crowd(rng, 30)
    origins, directions = rays_into_crowd(rng, 20_000)
    expected = cast(scene, origins, directions)
    got = _offer_all(compiled.scene_arrays(scene), scene.object_count, origins, directions)
    assert np.array_equal(got[:, 0], expected.index) and (expected.index >= 0).mean() > 0.05
    exactly(got[:, 1], expected.t)
    exactly(got[:, 2:], expected.color)


CHECKS = {"hits.keep_nearer": _keep_nearer}
test_the_twin_repeats_its_reference = twin_test("hits", CHECKS)

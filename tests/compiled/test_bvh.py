"""The tree walk (raykit.engine.compiled.bvh) against raykit.render.cast, with ties and holes."""

from __future__ import annotations

from dataclasses import replace

import numba
import numpy as np
import pytest

from raykit.engine import bvh, compiled
from raykit.engine.compiled import bvh as kernels
from raykit.render import cast

from .harness import (
    RAYS,
    caster_answers_what_cast_answers,
    crowd,
    exactly,
    random_rays,
    rays_into_crowd,
    twin_test,
)


@pytest.mark.parametrize("objects", [3, 40, 300])
def test_bvh_caster_answers_what_cast_answers_with_ties_and_holes(objects):
    rng = np.random.default_rng(objects)
    scene = crowd(rng, objects)
    if objects < 4:  # few enough that each ray tests every object (DIRECT_HITS): add a tie
        twin = replace(scene.spheres[0], color=np.array([1.0, 0.0, 1.0]))
        scene = replace(scene, spheres=(*scene.spheres, twin))
    direct = len(scene.spheres) + len(scene.billboards) <= compiled.DIRECT_HITS
    assert direct == (objects < 4)  # the small crowd takes that path, the others the tree's
    origins, directions = rays_into_crowd(rng, RAYS)
    expected = cast(scene, origins, directions)
    got = compiled.caster(scene)(origins, directions)
    assert np.array_equal(got.index, expected.index)
    exactly(got.t, expected.t)
    exactly(got.color, expected.color)
    assert (expected.index >= 0).mean() > 0.05  # thousands of hits, and misses
    assert (expected.index == 0).sum() > 25  # rays that meet sphere 0 and its twin at one t


@numba.njit
def _enters_each(origins, inverse, lower, upper, t_max):
    out = np.empty(len(origins), dtype=np.bool_)
    for i in range(len(origins)):
        o, v = origins[i], inverse[i]
        out[i] = kernels.enters(o[0], o[1], o[2], v[0], v[1], v[2], lower, upper, i, t_max[i])[0]
    return out


def _enters(rng):
    count = 20_000
    origins, directions = random_rays(rng, count, 3.0)
    directions[::5, rng.integers(0, 3)] = 0.0  # parallel to a slab: an infinite inverse
    origins[::10, 0] = 1.0  # ... some starting on its face
    along = origins + directions * rng.uniform(-2, 8, size=(count, 1))  # boxes near each ray
    lower = along - rng.uniform(0, 2, size=(count, 3))
    upper = along + rng.uniform(-1, 2, size=(count, 3))
    lower[::10, 0] = 1.0
    with np.errstate(divide="ignore"):
        inverse = 1.0 / directions
    t_max = np.where(rng.uniform(size=count) < 0.5, np.inf, rng.uniform(0, 10, size=count))
    expected = bvh._enters(origins, inverse, lower, upper, t_max)
    assert 0.1 < expected.mean() < 0.9
    assert np.array_equal(_enters_each(origins, inverse, lower, upper, t_max), expected)


CHECKS = {
    "bvh.nearest_hit": caster_answers_what_cast_answers,  # cast_rays: a nearest_hit per ray
    "bvh.enters": _enters,
}
test_the_twin_repeats_its_reference = twin_test("bvh", CHECKS)

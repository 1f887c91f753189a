"""Repeats :mod:`raykit.lights` for one point: the unit vector l toward a point light, where on
an area light a shadow ray aims, and the intensity it sends from there."""

from __future__ import annotations

import math

from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY
from raykit.engine.compiled.sampling import point_on_parallelogram


@njit(**ONE_RAY)
def toward_point_light(v0, v1, v2, p0, p1, p2):
    """Repeats :func:`raykit.lights.toward_light` for a point light at v: the unit l from p,
    and the distance."""
    to0, to1, to2 = v0 - p0, v1 - p1, v2 - p2
    distance = math.sqrt(to0 * to0 + to1 * to1 + to2 * to2)
    return to0 / distance, to1 / distance, to2 / distance, distance


@njit(**ONE_RAY)
def area_light(shading, j):
    """Area light j of ``shading`` as :func:`area_intensity` takes it, numbers read once: whether
    it is physically based, its colour (r, g, b), unit normal (n0, n1, n2) and area A. (Read
    from the arrays in a loop over many points, they might be among the arrays that the loop
    writes, to the compiler, which then kept the loop one point at a time.)"""
    color, normal = shading.light_colors, shading.light_normals
    return (shading.physical[j], color[j, 0], color[j, 1], color[j, 2], normal[j, 0],
            normal[j, 1], normal[j, 2], shading.light_area[j])  # fmt: skip


@njit(**ONE_RAY)
def area_intensity(light, l0, l1, l2, distance):
    """Repeats :func:`raykit.lights.area_intensity` for one point: the intensity I of the area
    ``light`` (:func:`area_light`) toward it, l the unit vector to its sampled point and
    ``distance`` the distance: the light's colour (FOCG's), or a physically based light's
    L·A·cos θ_L/(π·r²)."""
    physical, c0, c1, c2, n0, n1, n2, area = light
    if not physical:
        return c0, c1, c2
    cos_light = -(l0 * n0 + l1 * n1 + l2 * n2)
    facing = cos_light if cos_light > 0 else 0.0  # the back of the light: none (NaN too)
    share = area * facing / (math.pi * distance * distance)
    return c0 * share, c1 * share, c2 * share


@njit(**ONE_RAY)
def sampled(shading, j, u1, u2):
    """Repeats :func:`raykit.lights.sampled` for one point: area light j (of ``shading``,
    :class:`~raykit.engine.compiled.scene.Shading`) as a point light at c + ξ1·a + ξ2·b, its
    position (its colour is the light's)."""
    corner, edges = shading.light_vectors, shading.light_edges
    return point_on_parallelogram(corner[j, 0], corner[j, 1], corner[j, 2], edges[j, 0],
                                  edges[j, 1], edges[j, 2], edges[j, 3], edges[j, 4], edges[j, 5],
                                  u1, u2)  # fmt: skip

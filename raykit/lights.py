"""Lights, and the unit vector l from a surface point toward each one (FOCG 4.5).

Conventions (shared by :mod:`raykit.shading`, :mod:`raykit.shadows` and :mod:`raykit.mirrors`)
---------------------------------------------------------------------------------------------
* Every vector of the shading formulas is unit length and points *away* from the surface
  point p: l toward the light, v toward the viewer (v = -d), n the surface normal, h the
  half vector, r the mirror direction.
* A directional light (the sun) shines along ``direction``: the way its light *travels*, from
  the light into the scene. So l = -direction / |direction|, the same at every point, and the
  light is infinitely far away.
* A point light sits at ``position``: l = (position - p) / |position - p|, and the light is
  |position - p| away. Its intensity does not fall off with distance (as in FOCG 4.5; a
  physically based renderer would divide by the distance squared).
* An area light (stage 5, FOCG 13.4.2) is a parallelogram, like a billboard: the points
  c + ξ1·a + ξ2·b, ξ1, ξ2 in [0, 1], of its ``corner`` c and edges ``edge1`` a and ``edge2`` b
  (:func:`raykit.sampling.point_on_parallelogram`). It is *sampled*: each shading point aims its
  shadow ray at its own point of the light (:func:`sampled`), and from there the light is a point
  light, so a soft shadow is the mean over many samples. Of what intensity, two models
  (:func:`area_intensity`):

  - FOCG's, the lecture's and the default: the light's colour I, whatever the distance and the
    angle at which the light is seen, as a point light's; a light shrunk to a point is the
    point light. A simplification: a lamp twice as far lights as brightly, and a panel seen
    edge-on as brightly as face-on.
  - the physically based one (``physical``, the scene file's ``radiance``), as Mitsuba, pbrt and
    every physically based renderer define an area light: its colour is a *radiance* L, and
    what a surface receives falls off with the squared distance and with the cosine at the
    light; it lights only the side that a × b points to. A diffuse surface under it gets
    exactly what such a renderer computes.
* A light's ``color`` is its intensity I per channel, >= 0; it may exceed 1 for a bright light
  (a physically based area light's, its radiance L).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from raykit.rays import cross, dot, normalize
from raykit.sampling import point_on_parallelogram

LIGHT_TYPES = ("directional", "point", "area")


@dataclass(frozen=True)
class DirectionalLight:
    """Light from infinitely far away, travelling along ``direction (3,)``; ``color (3,)``."""

    direction: np.ndarray
    color: np.ndarray


@dataclass(frozen=True)
class PointLight:
    """Light from ``position (3,)`` in every direction; ``color (3,)``."""

    position: np.ndarray
    color: np.ndarray


@dataclass(frozen=True)
class AreaLight:
    """Light from the parallelogram ``corner`` + ξ1·``edge1`` + ξ2·``edge2`` (each ``(3,)``),
    sampled a point per shadow ray; ``color (3,)``: FOCG's intensity I, or with ``physical``
    the radiance L of a physically based area light (:func:`area_intensity`)."""

    corner: np.ndarray
    edge1: np.ndarray
    edge2: np.ndarray
    color: np.ndarray
    physical: bool = False

    @property
    def frame(self) -> tuple[float, np.ndarray]:
        """Its area A = |a × b| and unit normal n_L = (a × b)/A ``(3,)``, the side it lights
        when it is physically based."""
        normal = cross(np.asarray(self.edge1, float), np.asarray(self.edge2, float))
        area = float(np.sqrt(dot(normal, normal)))
        return area, normal / area


Light = DirectionalLight | PointLight | AreaLight


def sampled(light: AreaLight, uniforms: np.ndarray) -> PointLight:
    """The area light as point lights, one per shading point: positions ``(N, 3)`` on it from
    ``uniforms (N, 2)`` (:func:`raykit.sampling.point_on_parallelogram`), the same colour. A
    stage-5 student function."""
    # BEGIN SOLUTION
    # hint: a PointLight whose position (N, 3) is the point of the parallelogram each row of
    #       uniforms chooses (point_on_parallelogram), with the light's colour
    return PointLight(
        point_on_parallelogram(light.corner, light.edge1, light.edge2, uniforms), light.color
    )
    # END SOLUTION


def area_intensity(light: AreaLight, l: np.ndarray, distance: np.ndarray) -> np.ndarray:
    """The intensity I ``(N, 3)`` that an area light's sampled points (:func:`sampled`) send to
    the surface points they light: ``l (N, 3)``, the unit vector from each point toward its
    point q of the light, and ``distance (N,)`` r = |q - p| (:func:`toward_light`).

    FOCG's light: I = the light's colour, for every point.

    The physically based light, of radiance L (its colour), area A = |a × b| and unit normal
    n_L = (a × b)/A (:attr:`AreaLight.frame`). A diffuse surface (BRDF kd/π) at p, with normal
    n, reflects toward the eye the light that reaches it from every point q of the light:

        L_r(p) = ∫_light (kd/π) · L · cos θ · cos θ_L / r² · V(p, q) dA(q),

    θ the angle at p between n and l, θ_L the angle at q between n_L and -l, V 1 where nothing
    blocks the segment and 0 where something does (the shadow ray); dA(q)·cos θ_L/r² is the
    solid angle the patch dA fills, seen from p. A point q uniform on the light has the density
    1/A, so the mean of the integrand over N such points, each divided by 1/A, estimates it:

        L_r(p) ≈ (1/N) Σ_k kd · [L·A·cos θ_L,k/(π·r_k²)] · cos θ_k · V_k.

    Each term is FOCG's Lambert term kd·I·max(0, n·l) (:func:`raykit.shading.lambert`), a point
    light's, with the point light's I the bracket: I_k = L·A·max(0, -n_L·l)/(π·r_k²). So the
    renderer samples both models alike, and only I differs; FOCG's model is the same sum with
    I_k = I, no fall-off, no cosine at the light (and an intensity, where L is a radiance: no π,
    no A). The back of the light (n_L·l >= 0) gives I = 0, as a physically based renderer's
    one-sided emitter. The highlight takes the same I (Blinn-Phong's term is the lecture's, not
    a physically based one: a diffuse scene is what both kinds of renderer render alike)."""
    if not light.physical:
        return np.broadcast_to(np.asarray(light.color, float), (len(l), 3))
    area, normal = light.frame
    cos_light = -dot(l, normal)
    facing = np.where(cos_light > 0, cos_light, 0.0)  # the back of the light: none (NaN too)
    share = area * facing / (math.pi * distance * distance)  # I_k / L
    return np.asarray(light.color, float) * share[:, None]


def toward_light(light: Light, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors l ``(N, 3)`` from surface points ``(N, 3)`` to the light, and the distance
    to it ``(N,)`` (inf for a directional light): a shadow ray's blocker counts only if nearer.
    A point light's ``position`` may be ``(N, 3)``, one per point (an area light,
    :func:`sampled`)."""
    # BEGIN SOLUTION
    # hint: directional: l = -direction (normalised), distance inf; point: l = position - p,
    #       normalised, distance |position - p|
    if isinstance(light, DirectionalLight):
        l = np.broadcast_to(normalize(-np.asarray(light.direction, float)), points.shape)
        return l, np.full(len(points), np.inf)
    to_light = np.asarray(light.position) - points
    distance = np.sqrt(dot(to_light, to_light))
    return to_light / distance[:, None], distance
    # END SOLUTION

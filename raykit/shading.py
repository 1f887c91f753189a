"""Shading (FOCG 4.5–4.9): the colour of a hit point from its lights, shadows and mirrors.

The book's model, per colour channel, with every vector unit length and pointing away from the
surface point (the conventions of :mod:`raykit.lights`):

    L = ka·Ia + Σ_lights visible [ kd·I·max(0, n·l) + ks·I·max(0, n·h)^p ] + km·L(r)

* ka·Ia: ambient light, the same everywhere (ka = kd, :mod:`raykit.materials`);
* kd·I·max(0, n·l): Lambert's diffuse term, :func:`lambert`;
* ks·I·max(0, n·h)^p with h = (l + v)/|l + v| and v = -d: Blinn-Phong's highlight,
  :func:`blinn_phong`; where l + v = 0 exactly, h is undefined and there is no highlight;
* "visible": the light is not blocked (:mod:`raykit.shadows`). A light behind the surface
  (n·l <= 0) adds nothing, highlight included: it cannot light the side it does not reach;
* an area light (stage 5, FOCG 13.4.2) is, for each ray, a point light at its own sampled
  point of the light (:func:`raykit.lights.sampled`): one shadow ray per ray and light, the
  penumbra the mean over a pixel's samples. The uniform numbers come with the rays
  (``light_uniforms``); without them each area light is sampled at its centre. Its I is its
  colour (FOCG's), or for a physically based light, each point's own, which falls off with
  the distance and the cosine at the light (:func:`raykit.lights.area_intensity`, which
  derives the estimator);
* km·L(r): what the mirror reflects (:mod:`raykit.mirrors`); a glossy mirror (stage 5, FOCG
  13.4.4) reflects along r', r perturbed by the ray's own uniform numbers (``gloss_uniforms``),
  and an r' below the surface is absorbed: that ray's mirror term is black;
* motion blur (stage 5): a ray with a time (``times``) sees the moving spheres where they are
  at that time, and so do its shadow and mirror rays: they belong to the same instant.

A scene with no lights and no ambient (every format v1 scene) is unlit: L is the object's flat
colour (plus km·L(r) on mirrors). Colours add up unclamped; the image clamps to [0, 1] when it
is quantised (:mod:`raykit.io.images`).

What is skipped. The renderer calls :func:`shade` only when a scene has lights, ambient light or
a mirror; shadow rays are cast only for points facing a light, and only when the scene's
``shadows`` is on and it has two objects or more (a sphere or billboard cannot shadow itself
where it faces the light), and each is tested only against objects that can lie between its
point and the light (:func:`raykit.engine.regions.cast_nearby`, or the BVH); the highlight is
computed only on objects with a specular colour; mirror rays start only on mirrors.
"""

from __future__ import annotations

from dataclasses import replace
from functools import partial

import numpy as np

from raykit.hits import Hits
from raykit.lights import AreaLight, area_intensity, sampled, toward_light
from raykit.mirrors import glossy_reflect, reflect
from raykit.rays import dot, normalize
from raykit.scene import Scene
from raykit.shadows import Caster, in_shadow, light_reach
from raykit.surfaces import SurfacePoints, surface_points


def lambert(kd: np.ndarray, intensity: np.ndarray, n: np.ndarray, l: np.ndarray) -> np.ndarray:
    """Lambert's diffuse term kd·I·max(0, n·l) ``(N, 3)``: ``kd (N, 3)``, light intensity I
    ``(3,)`` (or each point's, ``(N, 3)``), unit normals ``n`` and unit vectors toward the light
    ``l``, both ``(N, 3)``."""
    # BEGIN SOLUTION
    # hint: kd · I · max(0, n·l), with n·l per row (raykit.rays.dot) made a column to scale the
    #       colours
    return kd * intensity * np.maximum(0.0, dot(n, l))[:, None]
    # END SOLUTION


def blinn_phong(
    ks: np.ndarray,
    intensity: np.ndarray,
    n: np.ndarray,
    l: np.ndarray,
    v: np.ndarray,
    p: np.ndarray | float,
) -> np.ndarray:
    """Blinn-Phong's highlight ks·I·max(0, n·h)^p ``(N, 3)`` with the half vector
    h = (l + v)/|l + v|: ``ks (N, 3)``, I ``(3,)`` (or ``(N, 3)``), unit ``n``, ``l`` and ``v``
    (toward the viewer) ``(N, 3)``, shininess ``p`` a number or ``(N,)``."""
    # BEGIN SOLUTION
    # hint: h = normalize(l + v) (raykit.rays.normalize); then ks · I · max(0, n·h)^p, the power
    #       taken per row
    h = normalize(l + v)
    return ks * intensity * (np.maximum(0.0, dot(n, h)) ** p)[:, None]
    # END SOLUTION


def casts_shadows(scene: Scene) -> bool:
    """Whether shadow rays are needed: shadows on, lights, and two objects or more."""
    return scene.shadows and bool(scene.lights) and scene.object_count > 1


def needs_shading(scene: Scene) -> bool:
    """Whether anything beyond v1's flat colours is asked for: light or a mirror."""
    return scene.lit or scene.materials.any_mirror


def shade(
    scene: Scene,
    cast: Caster,
    origins: np.ndarray,
    directions: np.ndarray,
    hits: Hits,
    light_uniforms: np.ndarray | None = None,
    *,
    gloss_uniforms: np.ndarray | None = None,
    times: np.ndarray | None = None,
) -> np.ndarray:
    """Colours ``(N, 3)`` of rays ``(N, 3)`` (unit directions) with their nearest ``hits``
    (object indices of ``scene``). ``cast`` finds the nearest hits of secondary rays over the
    whole scene (a diagram that wants to see those rays wraps it: :mod:`raykit.diagrams.rays`).
    ``light_uniforms (N, max_depth + 1, A, 2)``: each ray's uniform numbers for the A area
    lights (in the order of ``scene.lights``) at each mirror depth. ``gloss_uniforms
    (N, max_depth, 2)``: each ray's numbers for the glossy perturbation of its mirror bounce at
    each depth (None: glossy mirrors reflect as ideal ones). ``times (N,)``: each ray's time in
    the shutter interval, which its shadow and mirror rays share (``cast`` then takes
    ``times=``; None: the scene as it stands)."""
    count = len(origins)
    colors = np.zeros((count, 3))
    weight = np.ones((count, 3))  # what one unit of light along the ray adds to its pixel
    ray = np.arange(count)  # the primary ray each current ray belongs to
    mirror = scene.materials.mirror
    for depth in range(scene.max_depth + 1):
        hit = hits.index >= 0
        colors[ray[~hit]] += weight[~hit] * hits.color[~hit]  # the background
        origins, directions, ray, weight = origins[hit], directions[hit], ray[hit], weight[hit]
        index, color = hits.index[hit], hits.color[hit]
        if not len(index):
            break
        at = None if times is None else times[ray]
        surface = surface_points(scene, origins, directions, hits.t[hit], index, at)
        on_lights = None if light_uniforms is None else light_uniforms[ray, depth]
        colors[ray] += weight * surface_color(
            scene, cast, surface, directions, index, color, on_lights, times=at
        )
        km = mirror[index]
        bounce = np.flatnonzero(km.any(axis=1))
        if depth == scene.max_depth or not len(bounce):
            break
        d, n = directions[bounce], surface.normals[bounce]
        if gloss_uniforms is None:
            directions = reflect(d, n)
        else:  # a perturbed ray below the surface is absorbed: it goes no further
            glossiness = scene.materials.glossiness[index[bounce]]
            directions, above = glossy_reflect(d, n, glossiness, gloss_uniforms[ray[bounce], depth])
            bounce, directions = bounce[above], directions[above]
        origins = surface.take(bounce).start(directions)
        ray, weight = ray[bounce], weight[bounce] * km[bounce]
        hits = (
            cast(origins, directions)
            if times is None
            else cast(origins, directions, times=times[ray])
        )
    return colors


def surface_color(
    scene: Scene,
    cast: Caster,
    surface: SurfacePoints,
    directions: np.ndarray,
    index: np.ndarray,
    color: np.ndarray,
    light_uniforms: np.ndarray | None = None,
    *,
    times: np.ndarray | None = None,
) -> np.ndarray:
    """A surface's own colour ``(N, 3)`` at hit points (all but the mirror term): the flat
    ``color (N, 3)`` in an unlit scene, else ambient + each visible light's Lambert and
    Blinn-Phong terms. ``index (N,)``: the objects hit. ``light_uniforms (N, A, 2)``: where on
    each of the A area lights each point's shadow ray aims (None: at the light's centre).
    ``times (N,)``: the time of each point's ray, at which its shadow rays look for blockers."""
    if not scene.lit:
        return color
    table = scene.materials
    kd = np.where(table.has_diffuse[index][:, None], table.diffuse[index], color)
    ambient = scene.ambient if scene.ambient is not None else np.zeros(3)
    total = kd * ambient
    v = -directions
    shiny = table.specular[index].any(axis=1)
    shadows = casts_shadows(scene)
    areas = 0  # area lights so far
    for light in scene.lights:
        area = isinstance(light, AreaLight)
        if area:  # a point light per surface point, at its own point of the light
            if light_uniforms is None:
                on_light = np.full((len(surface.points), 2), 0.5)
            else:
                on_light = light_uniforms[:, areas]
            panel, light, areas = light, sampled(light, on_light), areas + 1
        l, distance = toward_light(light, surface.points)  # the shadow ray's: light_reach
        intensity = light.color  # I (3,), or a physically based area light's at each point
        if area and panel.physical:
            intensity = area_intensity(panel, l, distance)
        lit = np.flatnonzero(dot(surface.normals, l) > 0)
        if shadows and len(lit):
            facing = surface.take(lit)
            reaching = replace(light, position=light.position[lit]) if area else light
            reach = light_reach(facing, l[lit], reaching)  # from the offset start, less its margin
            blockers = cast if times is None else partial(cast, times=times[lit])  # that instant
            lit = lit[~in_shadow(blockers, facing, l[lit], reach)]
        n = surface.normals
        total[lit] += lambert(kd[lit], _rows(intensity, lit), n[lit], l[lit])
        highlight = lit[shiny[lit]]
        # h = (l + v)/|l + v| is undefined where l + v = 0 (seen from inside a sphere, a light
        # straight behind the point): no highlight there, rather than NaN
        highlight = highlight[np.any(l[highlight] + v[highlight] != 0, axis=1)]
        if len(highlight):
            which = index[highlight]
            total[highlight] += blinn_phong(
                table.specular[which],
                _rows(intensity, highlight),
                n[highlight],
                l[highlight],
                v[highlight],
                table.shininess[which],
            )
    return total


def _rows(intensity: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """A light's I for the points ``rows``: its one I ``(3,)``, or those rows of each point's
    ``(N, 3)`` (a physically based area light's)."""
    return intensity if intensity.ndim == 1 else intensity[rows]

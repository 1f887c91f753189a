"""Forward light tracing: photons from the lights, one diffuse bounce, onto the image.

The slides' paths of light run from the light to a surface to the eye. A renderer can follow
them *backward*, from the eye (:func:`raykit.render.render`: one ray per pixel, then a shadow
ray to each light), or *forward*, as light does: photons leave each light in random directions,
most of them never reach the camera, and an image builds up from those that do.
:func:`forward_render` is the forward one, for the quantity it can be compared on:

    the direct diffuse term  Σ_point lights not blocked  kd·I·max(0, n·l)

of :mod:`raykit.shading` (Lambert's term with shadows; no ambient, no highlight, no mirrors, a
black background), averaged over each pixel's area. :func:`diffuse_only` makes the scene whose
backward render is that term, so ``render(diffuse_only(scene), samples=n).rgb`` is the backward
estimate with n x n samples per pixel, and both converge to the same image.

One photon, from point light j (perspective cameras only; a directional light has no place to
start photons from):

1. it leaves the light's position x_L in a uniformly random direction (density 1/4π per unit
   solid angle) and stops at the first surface it meets, p, at distance r_L (a surface the light
   cannot reach gets no photon: shadows come for free);
2. it bounces off p diffusely. A pinhole is a point, which a random bounce never passes, so the
   bounce is counted by its density toward the hole (the standard light-tracing estimator):
   if the eye e sees p (p faces e, nothing lies between, and p projects into the image), the
   photon lands on the image plane where the line p–e crosses it, in pixel j, adding

       kd·I·4π·r_L² · d²·cos θ_e / (r_e²·cos³ α · A_pixel) / N_photons

   where r_e = |e − p|, cos θ_e = n·(e − p)/r_e, α the angle between the line and the view
   direction −w, d the distance to the image plane and A_pixel a pixel's area on it. (The
   pixel's value is (1/A_pixel)∫ L dx over its area; dx = d²·cos θ_e·dA/(r_e²·cos³ α) turns the
   integral into one over surface area, and the photons hit surface area with density
   cos θ_L/(4π·r_L²), which cancels the max(0, n·l) = cos θ_L of L and leaves r_L²: raykit's
   lights do not fall off with distance.)

:class:`ForwardStats` counts how many photons hit anything, how many land on the image, and how
many would arrive through a real pinhole of radius ``aperture`` if bounced at random: for a
cosine-distributed bounce, that share is cos θ_e·cos α·aperture²/r_e² per landed photon.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from raykit.lights import PointLight
from raykit.rays import dot, length
from raykit.render import secondary_caster
from raykit.scene import Scene
from raykit.surfaces import surface_points

BATCH = 65_536  # photons traced at once


@dataclass
class ForwardStats:
    """What happened to the photons: ``emitted``, ``hit`` (met a surface), ``landed`` (seen by
    the eye on the image: counted by their density toward the pinhole) and ``through_hole``,
    the expected number that a random diffuse bounce would send through a pinhole of radius
    ``aperture``."""

    emitted: int = 0
    hit: int = 0
    landed: int = 0
    through_hole: float = 0.0
    aperture: float = 1e-3


def diffuse_only(scene: Scene) -> Scene:
    """The scene whose backward render is the direct diffuse term that :func:`forward_render`
    estimates: black background, no ambient light, no highlights, no mirrors, shadows on."""
    if not scene.lights or not all(isinstance(light, PointLight) for light in scene.lights):
        raise ValueError("forward tracing needs point lights (photons start at their positions)")

    def plain(obj):
        return replace(
            obj, material=replace(obj.material, specular=np.zeros(3), mirror=np.zeros(3))
        )

    return replace(
        scene,
        spheres=tuple(plain(s) for s in scene.spheres),
        billboards=tuple(plain(b) for b in scene.billboards),
        background=np.zeros(3),
        ambient=None,
        shadows=True,
    )


def forward_render(
    scene: Scene, photons: int, seed: int = 0, aperture: float = 1e-3
) -> tuple[np.ndarray, ForwardStats]:
    """The direct diffuse term of ``scene`` (see the module docstring) estimated from
    ``photons`` photons per light: ``rgb (H, W, 3)`` and :class:`ForwardStats`. Seeded."""
    scene = diffuse_only(scene)
    camera = scene.camera
    if camera.projection != "perspective":
        raise ValueError("forward tracing needs a perspective camera (a pinhole)")
    rng = np.random.default_rng(seed)
    cast = secondary_caster(scene)
    image = np.zeros((camera.height * camera.width, 3))
    stats = ForwardStats(aperture=aperture)
    for light in scene.lights:
        done = 0
        while done < photons:
            count = min(BATCH, photons - done)
            done += count
            _trace_batch(scene, cast, light, count, rng, image, stats)
    image *= 4.0 * np.pi / photons
    return image.reshape(camera.height, camera.width, 3), stats


def _trace_batch(scene, cast, light, count, rng, image, stats) -> None:
    """Trace ``count`` photons from ``light``, adding each landed one (unscaled) to ``image``."""
    camera = scene.camera
    stats.emitted += count
    directions = rng.normal(size=(count, 3))  # uniform on the sphere once normalised
    directions /= length(directions)[:, None]
    origins = np.broadcast_to(np.asarray(light.position, float), directions.shape)
    hits = cast(origins, directions)
    hit = np.flatnonzero(hits.index >= 0)
    stats.hit += len(hit)
    if not len(hit):
        return
    index, r_light, color = hits.index[hit], hits.t[hit], hits.color[hit]
    surface = surface_points(scene, origins[hit], directions[hit], r_light, index)
    p, n = surface.points, surface.normals
    # a billboard's normal faces the photon; a sphere's points outward, the side photons reach
    eye = np.asarray(camera.eye, float)
    to_eye = eye - p
    r_eye = length(to_eye)
    cos_eye = dot(n, to_eye) / r_eye
    u, v, w = camera.frame
    depth = dot(to_eye, w)  # (p - e)·(-w): in front of the eye when > 0
    with np.errstate(divide="ignore", invalid="ignore"):
        s = camera.d * dot(p - eye, u) / depth
        t = camera.d * dot(p - eye, v) / depth
    Wp, Hp = camera.plane_size
    x = (s + Wp / 2) * camera.width / Wp
    y = (Hp / 2 - t) * camera.height / Hp
    inside = (cos_eye > 0) & (depth > 0) & (x >= 0) & (x < camera.width)
    inside &= (y >= 0) & (y < camera.height)
    candidates = np.flatnonzero(inside)
    # the eye sees p if its ray toward p meets this object first, at p
    seen_from_eye = cast(
        np.broadcast_to(eye, (len(candidates), 3)),
        -to_eye[candidates] / r_eye[candidates, None],
    )
    same = (seen_from_eye.index == index[candidates]) & (
        np.abs(seen_from_eye.t - r_eye[candidates]) <= 1e-7 * (r_eye[candidates] + 1.0)
    )
    landed = candidates[same]
    stats.landed += len(landed)
    if not len(landed):
        return
    # cubed below as a product: numpy's ** 3 is a vectorised power whose last bit differs
    # between processors (tests/test_machine_independent.py)
    cos_alpha = depth[landed] / r_eye[landed]
    table = scene.materials
    which = index[landed]
    kd = np.where(table.has_diffuse[which][:, None], table.diffuse[which], color[landed])
    pixel_area = (Wp / camera.width) * (Hp / camera.height)
    weight = (
        r_light[landed] ** 2
        * camera.d**2
        * cos_eye[landed]
        / (r_eye[landed] ** 2 * (cos_alpha * cos_alpha * cos_alpha) * pixel_area)
    )
    stats.through_hole += float(
        np.sum(cos_eye[landed] * cos_alpha * stats.aperture**2 / r_eye[landed] ** 2)
    )
    pixel = y[landed].astype(np.intp) * camera.width + x[landed].astype(np.intp)
    contribution = kd * np.asarray(light.color, float) * weight[:, None]
    for channel in range(3):
        image[:, channel] += np.bincount(
            pixel, weights=contribution[:, channel], minlength=len(image)
        )

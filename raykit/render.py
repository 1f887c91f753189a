"""The renderer: for every pixel, the nearest object its ray hits, and that object's colour.

This is the lecture's ray-tracing loop, as the slide writes it::

    for each pixel {
        compute viewing ray
        intersect ray with scene
        compute illumination at intersection
        store resulting color at pixel
    }

(to intersect a ray with the scene is to find the nearest object it hits), run for many pixels
at once (numpy arrays instead of a per-pixel Python loop): a batch is a tile of pixels at one
sample offset. Which pixels, rays and objects go together is the
engine's business (:mod:`raykit.engine.regions`): it skips what cannot be seen and never
changes a pixel. Conventions: pixels and rays per :mod:`raykit.camera`, object indices per
:mod:`raykit.scene`, colours are linear floats in [0, 1] with no gamma.

Colour. A scene without lights, ambient light or mirrors (every scene of format v1) shows each
object's flat colour, and nothing else runs. Otherwise each sample's hit is shaded
(:mod:`raykit.shading`): its shadow and mirror rays go through the whole scene.

With n x n samples per pixel (:func:`raykit.camera.sample_offsets`), the pixel's colour is the
mean of its samples' colours, taken before quantising to 8 bits (:mod:`raykit.io.images`). The
``object_index`` and ``t`` images always describe the ray through the pixel *centre* (the
pinhole's ray, with a lens).

Distributed ray tracing (stage 5, FOCG 13.4). A scene with more than one sample per pixel, an
area light, a lens, a glossy mirror or a sphere moving in the shutter interval is rendered the
same way, a sample at a time: each sample of a pixel has
its own point in the pixel, on the lens and on each area light, its own perturbation of each
glossy mirror's reflection and its own time in the shutter interval, from the sampler the scene
names (:mod:`raykit.sampling`), and the pixel is the mean of its samples. The same seed gives
the same bytes (:mod:`raykit.engine.noise`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from raykit.billboards import billboard_color_at, hit_billboard
from raykit.camera import rays_through
from raykit.engine import regions
from raykit.engine.adaptive import edge_pixels, refine
from raykit.engine.choice import choose
from raykit.engine.regions import Image, Plan, ViewingRays
from raykit.hits import Hits, solid
from raykit.scene import Scene
from raykit.shading import shade
from raykit.shadows import Caster
from raykit.spheres import center_at, hit_sphere


@dataclass(frozen=True)
class Render:
    """A rendered image: ``rgb (H, W, 3)`` float in [0, 1]; for the ray through each pixel
    centre, ``object_index (H, W)`` int (-1 for the background) and hit distance ``t (H, W)``
    (inf for the background), both None in a render of the picture alone (``hits=False``)."""

    rgb: np.ndarray
    object_index: np.ndarray | None
    t: np.ndarray | None


def render(
    scene: Scene,
    samples: int = 1,
    *,
    skip_hidden: bool = True,
    adaptive: bool = False,
    dtype: type = np.float64,
    progress: Callable[[int], object] | None = None,
    engine: str = "auto",
    hits: bool = True,
) -> Render:
    """Render ``scene`` with ``samples`` x ``samples`` rays per pixel.

    ``skip_hidden``: test each tile of pixels only against the objects that can be seen in it
    (:mod:`raykit.engine.tiles`); the image is the same either way, only the time differs.
    ``adaptive``: take the n x n samples only in pixels at an edge (:mod:`raykit.engine.adaptive`).
    ``dtype``: ``np.float32`` intersects in single precision, the scene moved to the eye first
    (:mod:`raykit.engine.precision`); the default float64 uses the scene as it is.
    ``progress``: called with each tile's pixel count as the tile is finished (width x height
    in all; with ``adaptive``, as the tile's edge pixels are refined); a progress bar's update.
    ``engine``: "numpy" runs the loop below; "compiled" runs the same loop as machine code, the
    same bits (:mod:`raykit.engine.compiled`, needs ``pip install "raykit[fast]"``); "auto"
    takes the compiled one only where that makes the whole run faster (:mod:`raykit.engine.choice`).
    ``hits``: False renders the picture alone, ``object_index`` and ``t`` None; where no sample
    passes through the pixel centre (an even n, a distributed scene), no ray is cast for them.
    """
    if choose(engine, scene, samples, dtype) == "compiled":
        from raykit.engine import compiled  # imports numba: only when it is used

        return Render(
            *compiled.render.render(scene, samples, adaptive=adaptive, progress=progress, hits=hits)
        )
    plan = Plan(
        scene, cast, samples, skip_hidden=skip_hidden, dtype=dtype, progress=progress, hits=hits
    )
    if adaptive and samples > 1:
        first = _adaptive(scene, plan)  # whose first render keeps the hits: edges are found by them
        return first if hits else Render(first.rgb, None, None)
    image = Image(plan)
    for batch in plan.batches():  # for each pixel (a tile of them, at one sample offset):
        rays = plan.viewing_rays(batch)  # compute the viewing ray
        hits = plan.nearest_hits(batch, rays)  # find the nearest object it hits
        colors = illumination(plan, rays, hits)  # "compute illumination at intersection"
        image.store(batch, rays, hits, colors)  # "store resulting color at pixel"
    return Render(image.mean(), image.object_index, image.t)


def illumination(plan: Plan, rays: ViewingRays, hits: Hits) -> np.ndarray:
    """The colours ``(M, 3)`` the rays see: the objects' flat colours in a scene of format v1,
    else their shading (:func:`raykit.shading.shade`) with shadow and mirror rays."""
    if plan.secondary is None:  # no light: "copy the color of the object at this point"
        return hits.color
    on_lights = plan.on_lights(rays)  # where on the area lights: a distributed render's
    gloss = plan.on_glossy(rays)  # how glossy mirrors perturb their rays, and
    return shade(  # each ray's time in the shutter interval (None: no such choice)
        plan.scene,
        plan.secondary,
        rays.origins,
        rays.directions,
        hits,
        on_lights,
        gloss_uniforms=gloss,
        times=rays.times,
    )


def _adaptive(scene: Scene, plan: Plan) -> Render:
    """One ray per pixel, then the n x n samples only at edges (:mod:`raykit.engine.adaptive`)."""
    first = render(scene, 1, skip_hidden=plan.skip_hidden, dtype=plan.dtype, engine="numpy")
    edge = edge_pixels(first.rgb, first.object_index)
    colors = lambda region, x, y: plan.colors_at(region, x, y, illumination)  # noqa: E731
    refine(plan.regions(), colors, first.rgb, edge, plan.samples, plan.progress)
    return first


def cast(
    scene: Scene, origins: np.ndarray, directions: np.ndarray, times: np.ndarray | None = None
) -> Hits:
    """The nearest hit of each ray ``(N, 3)`` over all objects of the scene; with ``times (N,)``
    (motion blur) each ray sees the moving spheres at its own time (None: as they stand)."""
    # BEGIN SOLUTION
    # hint: start from Hits.none, then offer every sphere and every billboard, in index order, to
    #       Hits.keep_nearer; with times, a sphere with a velocity (scene.velocities[i]) is at
    #       center_at(center, velocity, times), one centre per ray
    hits = Hits.none(len(origins), scene.background)
    moving = times is not None and scene.velocities is not None
    for i, sphere in enumerate(scene.spheres):
        center = sphere.center
        if moving and scene.velocities[i].any():
            center = center_at(sphere.center, scene.velocities[i], times)
        t = hit_sphere(origins, directions, center, sphere.radius)
        hits.keep_nearer(i, t, solid(sphere.color))
    for i, billboard in enumerate(scene.billboards, start=len(scene.spheres)):
        t, alpha, beta = hit_billboard(origins, directions, billboard)
        hits.keep_nearer(i, t, billboard_color_at(billboard, alpha, beta))
    return hits
    # END SOLUTION


def cast_pixels(
    scene: Scene, rows: np.ndarray, cols: np.ndarray
) -> tuple[np.ndarray, np.ndarray, Hits]:
    """The rays through the centres of pixels (rows, cols) ``(N,)`` and their nearest hits:
    ``origins (N, 3)``, ``directions (N, 3)`` and :class:`raykit.hits.Hits`. The same rays,
    and the same hits, as the pixel centres of :func:`render`."""
    origins, directions = rays_through(
        scene.camera, np.asarray(cols, float) + 0.5, np.asarray(rows, float) + 0.5
    )
    return origins, directions, cast(scene, origins, directions)


def secondary_caster(scene: Scene) -> Caster:
    """The nearest-hit function of shadow and mirror rays over the whole scene, as the
    renderer uses it (:func:`raykit.engine.regions.secondary_caster` over :func:`cast`)."""
    return regions.secondary_caster(scene, cast)

"""Distributed ray tracing, drawn (FOCG 13.4): the sampled rays of one pixel, an effect a figure.

Each diagram draws the rays that the samples of one pixel make, as the renderer makes them: the
same uniform numbers (:mod:`raykit.engine.noise`, from the scene's seed and sampler, for that
pixel) given to the same functions (:mod:`raykit.sampling`, :func:`raykit.camera.thin_lens_rays`,
:func:`raykit.mirrors.glossy_reflect`, :func:`raykit.render.cast` with the rays' times), over
the scene's objects in a top or side view (:mod:`raykit.diagrams.views`):

* :func:`pixel_samples_diagram` (antialiasing, 13.4.1): the pixel as the eye sees it, each
  sample's point in it coloured by what its ray hits; the pixel's colour is their mean;
* :func:`shadow_rays_diagram` (soft shadows, 13.4.2): from where the pixel's centre ray meets
  the scene, each sample's shadow ray to its own point of the area light, gold where it reaches
  the light, dark red up to an x where something blocks it, seen from the front; a pixel of the
  penumbra whose rays cross no ball in that view: :func:`penumbra_pixel`;
* :func:`lens_rays_diagram` (depth of field, 13.4.3): each sample's ray from its own point of
  the lens, all of them through one point of the focal plane (dashed);
* :func:`glossy_rays_diagram` (glossy reflection, 13.4.4): where the pixel's centre ray meets a
  glossy mirror, the mirror direction r (dashed) and each sample's perturbed r';
* :func:`moving_rays_diagram` (motion blur, 13.4.5): the rays of a few pixels, each sample's
  hit marked in the colour of its time T, over the moving spheres drawn where they are at the
  shutter's opening T0 (filled) and closing T1 (outlined).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from raykit.camera import camera_frame, rays_through, thin_lens_rays
from raykit.diagrams.views import (
    View,
    draw_lines,
    draw_outline,
    draw_scene_objects,
    finish_axes,
    new_axes,
    view_for,
)
from raykit.engine.noise import Dimensions, PixelSamples
from raykit.lights import AreaLight
from raykit.mirrors import glossy_reflect, reflect
from raykit.rays import length, normalize, point_at
from raykit.render import cast, cast_pixels
from raykit.sampling import point_in_pixel, point_on_parallelogram, shutter_times
from raykit.scene import Scene
from raykit.surfaces import surface_points

TIME_COLORS = "viridis"  # T0 dark blue to T1 yellow


def pixel_numbers(scene: Scene, row: int, col: int) -> tuple[np.ndarray, np.ndarray | None]:
    """The uniform numbers ``(S, dimensions)`` of the S samples of pixel (``row``, ``col``) as
    the renderer draws them (:class:`raykit.engine.noise.PixelSamples`), and the samples' times
    ``(S,)`` in a scene that moves (None otherwise)."""
    dimensions = Dimensions.of(scene)
    samples = PixelSamples(scene.sampling, dimensions.count)
    pixel = np.array([row * scene.camera.width + col])
    numbers = np.vstack([samples.of(pixel, k) for k in range(scene.sampling.samples_per_pixel)])
    if not scene.moving:
        return numbers, None
    shutter_open, shutter_close = scene.sampling.shutter
    if not scene.blurred:
        return numbers, np.full(len(numbers), float(shutter_open))
    times = shutter_times(shutter_open, shutter_close, samples.stratum(pixel, dimensions.time))
    return numbers, times[0]


def sample_rays(
    scene: Scene, row: int, col: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
    """The primary rays ``origins``, ``directions`` ``(S, 3)`` of the S samples of pixel
    (``row``, ``col``), through their points in the pixel and (with a lens) from their points
    on the lens, with the samples' numbers ``(S, dimensions)`` and times (:func:`pixel_numbers`)."""
    numbers, times = pixel_numbers(scene, row, col)
    count = len(numbers)
    x, y = point_in_pixel(np.full(count, row), np.full(count, col), numbers[:, 0:2])
    if scene.camera.aperture > 0:
        lens = Dimensions.lens
        origins, directions = thin_lens_rays(scene.camera, x, y, numbers[:, lens : lens + 2])
    else:
        origins, directions = rays_through(scene.camera, x, y)
    return origins, directions, numbers, times


def pixel_samples_diagram(scene: Scene, row: int, col: int, *, ax: Axes | None = None) -> Figure:
    """The pixel (``row``, ``col``) as the eye sees it: the unit square, its n x n cells, and
    each sample's point in it, coloured by what its ray hits (antialiasing, FOCG 13.4.1)."""
    origins, directions, numbers, times = sample_rays(scene, row, col)
    hits = cast(scene, origins, directions, times=times)
    if ax is None:
        ax = plt.figure(figsize=(4.6, 4.6), layout="constrained").add_subplot()
    n = int(np.sqrt(len(numbers)))
    for k in range(n + 1):
        ax.axhline(k / n, color="0.75", lw=0.8)
        ax.axvline(k / n, color="0.75", lw=0.8)
    ax.scatter(numbers[:, 0], numbers[:, 1], s=70, c=np.clip(hits.color, 0, 1),
               edgecolors="black", linewidths=0.8, zorder=3)  # fmt: skip
    ax.set_xlim(0, 1)
    ax.set_ylim(1, 0)  # ξ2 runs down the pixel, as the rows do
    ax.set_aspect("equal")
    ax.set_xlabel("ξ1 (across)")
    ax.set_ylabel("ξ2 (down)")
    ax.set_title(f"pixel ({row}, {col}): {len(numbers)} samples")
    return ax.figure


def _shadow_rays(scene: Scene, rows: np.ndarray, cols: np.ndarray) -> dict:
    """For pixels (``rows``, ``cols``) ``(P,)``, from where each centre ray meets the scene, the
    S samples' shadow rays to their own points of the first area light, as the renderer makes
    them: ``origins``, ``ends`` ``(P, 3)`` of the centre rays, the shadow rays' ``starts``,
    ``targets``, unit ``l`` ``(P, S, 3)``, the ``blockers`` (:class:`raykit.hits.Hits` of the
    P·S rays) and whether each is ``blocked`` ``(P, S)`` (a hit nearer than its point of the
    light)."""
    light = next(x for x in scene.lights if isinstance(x, AreaLight))
    origins, directions, hits = cast_pixels(scene, rows, cols)
    surface = surface_points(scene, origins, directions, hits.t, hits.index)
    dimensions = Dimensions.of(scene)
    samples = PixelSamples(scene.sampling, dimensions.count)
    pixels = np.asarray(rows) * scene.camera.width + np.asarray(cols)
    first = dimensions.light(0, 0)
    count = scene.sampling.samples_per_pixel
    numbers = np.stack([samples.of(pixels, k) for k in range(count)], axis=1)  # (P, S, D)
    on_light = numbers[..., first : first + 2].reshape(-1, 2)
    targets = point_on_parallelogram(light.corner, light.edge1, light.edge2, on_light)
    which = np.repeat(np.arange(len(pixels)), count)
    l = normalize(targets - surface.points[which])  # FOCG's l, toward the light
    starts = surface.take(which).start(l)
    blockers = cast(scene, starts, l)
    blocked = blockers.t < length(targets - starts)
    shape = (len(pixels), count)
    return {
        "origins": origins,
        "ends": point_at(origins, directions, hits.t),
        "starts": starts.reshape(*shape, 3),
        "targets": targets.reshape(*shape, 3),
        "l": l.reshape(*shape, 3),
        "blockers": blockers,
        "blocked": blocked.reshape(shape),
    }


def shadow_rays_diagram(
    scene: Scene, row: int, col: int, *, view: str = "front", ax: Axes | None = None
) -> Figure:
    """From where the centre ray of pixel (``row``, ``col``) meets the scene, each sample's
    shadow ray to its own point of the first area light (soft shadows, FOCG 13.4.2), seen from
    the front (across and up, as the eye sees the scene; the centre ray, along the line of
    sight, a dot where it meets the scene) by default."""
    light = next(x for x in scene.lights if isinstance(x, AreaLight))
    rays = _shadow_rays(scene, np.array([row]), np.array([col]))
    starts, targets, l = rays["starts"][0], rays["targets"][0], rays["l"][0]
    blocked, count = rays["blocked"][0], len(targets)
    shown, ax = _axes(scene, view, ax)
    corners = light.corner + np.array([np.zeros(3), light.edge1, light.edge1 + light.edge2,
                                       light.edge2])  # fmt: skip
    draw_outline(ax, shown, corners, colors="goldenrod", linewidths=3, zorder=5)
    if view == "front":  # the centre ray runs along the line of sight: its point, not its line
        ax.scatter(*shown.project(rays["ends"]).T, color="0.2", s=30, zorder=6)
    else:
        _rays(ax, shown, rays["origins"], rays["ends"], "0.3", "rays-centre")
    _rays(ax, shown, starts[~blocked], targets[~blocked], "goldenrod", "rays-shadow-reaching")
    stops = point_at(starts[blocked], l[blocked], rays["blockers"].t[blocked])
    _rays(ax, shown, starts[blocked], stops, "darkred", "rays-shadow-blocked")
    if blocked.any():
        ax.scatter(*shown.project(stops).T, marker="x", color="darkred", s=40, zorder=6)
    ax.set_title(f"{np.count_nonzero(~blocked)} of {count} shadow rays reach the light")
    drawn = [targets, starts, _spheres(scene)] + ([] if view == "front" else [rays["origins"]])
    finish_axes(ax, shown, np.vstack(drawn), scene.camera)
    return ax.figure


def penumbra_pixel(scene: Scene, view: str = "front") -> tuple[int, int]:
    """A pixel (row, column) in the penumbra of the scene's first area light, for
    :func:`shadow_rays_diagram`: its centre ray meets a surface from which some of its shadow
    rays reach the light and some are blocked, as near half as can be, and none of those that
    reach it crosses a sphere where ``view`` draws them (a ray passing beside a ball in space can
    be drawn across it, and would look as if it went through). Raises ValueError where no pixel
    is such."""
    height, width = scene.camera.height, scene.camera.width
    rows, cols = (grid.ravel() for grid in np.mgrid[0:height, 0:width])
    hit = cast_pixels(scene, rows, cols)[2].index >= 0
    rays = _shadow_rays(scene, rows[hit], cols[hit])
    share = rays["blocked"].mean(axis=1)
    shown = view_for(scene.camera, view)
    centres = shown.project(np.array([s.center for s in scene.spheres], float).reshape(-1, 3))
    radii = np.array([s.radius for s in scene.spheres], float)
    best = None
    for k in np.argsort(np.abs(share - 0.5), kind="stable"):
        if not 0 < share[k] < 1:
            break
        reaching = ~rays["blocked"][k]
        a = shown.project(rays["starts"][k][reaching])[:, None, :]  # (R, 1, 2)
        b = shown.project(rays["targets"][k][reaching])[:, None, :]
        d = b - a
        along = np.clip(np.sum((centres - a) * d, axis=-1) / np.sum(d * d, axis=-1), 0, 1)
        nearest = a + along[..., None] * d
        if (np.sqrt(np.sum((nearest - centres) ** 2, axis=-1)) > radii).all():
            best = k
            break
    if best is None:
        raise ValueError("no pixel of the penumbra has its shadow rays clear of the spheres")
    return int(rows[hit][best]), int(cols[hit][best])


def lens_rays_diagram(
    scene: Scene, row: int, col: int, *, view: str = "top", ax: Axes | None = None
) -> Figure:
    """Each sample's ray of pixel (``row``, ``col``) from its own point of the thin lens to what
    it hits, all through one point of the focal plane (dashed; depth of field, FOCG 13.4.3)."""
    origins, directions, _, times = sample_rays(scene, row, col)
    hits = cast(scene, origins, directions, times=times)
    camera = scene.camera
    _, _, w = camera_frame(camera.eye, camera.lookat, camera.up)
    ends = point_at(origins, directions, np.minimum(hits.t, 4 * camera.focus))
    shown, ax = _axes(scene, view, ax)
    plane_centre = camera.eye - camera.focus * w
    across = normalize(np.cross(w, camera.up)[None])[0] * camera.focus / 2
    draw_lines(ax, shown, np.array([[plane_centre - across, plane_centre + across]]),
               colors="0.4", linestyles="dashed", linewidths=1.2)  # fmt: skip
    _rays(ax, shown, origins, ends, np.clip(hits.color, 0, 1), "rays-lens")
    ax.set_title(f"{len(origins)} rays from the lens, focal plane dashed")
    finish_axes(ax, shown, np.vstack([origins, ends, _spheres(scene)]), camera)
    return ax.figure


def glossy_rays_diagram(
    scene: Scene, row: int, col: int, *, view: str = "top", ax: Axes | None = None
) -> Figure:
    """Where the centre ray of pixel (``row``, ``col``) meets a glossy mirror, the mirror
    direction r (dashed) and each sample's perturbed r' to what it meets (glossy reflection,
    FOCG 13.4.4); a ray perturbed below the surface (absorbed) is left out."""
    origins, directions, hits = cast_pixels(scene, np.array([row]), np.array([col]))
    surface = surface_points(scene, origins, directions, hits.t, hits.index)
    numbers, _ = pixel_numbers(scene, row, col)
    count = len(numbers)
    a = scene.materials.glossiness[hits.index[0]]
    gloss = Dimensions.of(scene).gloss(0)
    d, n = np.repeat(directions, count, axis=0), np.repeat(surface.normals, count, axis=0)
    r_prime, above = glossy_reflect(d, n, np.full(count, a), numbers[:, gloss : gloss + 2])
    r_prime = r_prime[above]
    starts = surface.take(np.zeros(len(r_prime), dtype=int)).start(r_prime)
    seen = cast(scene, starts, r_prime)
    span = float(length(np.ptp(_spheres(scene), axis=0)))  # how far a miss is drawn
    ends = point_at(starts, r_prime, np.minimum(seen.t, span))
    r = reflect(directions, surface.normals)
    mirror_t = cast(scene, surface.start(r), r).t
    shown, ax = _axes(scene, view, ax)
    _rays(ax, shown, origins, surface.points, "0.3", "rays-centre")
    _rays(ax, shown, starts, ends, np.clip(seen.color, 0, 1), "rays-glossy")
    mirror_end = point_at(surface.points, r, np.minimum(mirror_t, span))
    draw_lines(ax, shown, np.stack([surface.points, mirror_end], axis=1), colors="black",
               linestyles="dashed", linewidths=1.5, zorder=6)  # fmt: skip
    ax.set_title(f"glossiness a = {a:g}: r dashed, {len(r_prime)} rays r'")
    finish_axes(ax, shown, np.vstack([origins, ends, mirror_end, _spheres(scene)]), scene.camera)
    return ax.figure


def moving_rays_diagram(
    scene: Scene, pixels: list[tuple[int, int]], *, view: str = "top", ax: Axes | None = None
) -> Figure:
    """The sampled rays of ``pixels`` (row, col) in a scene that moves, each sample's ray drawn
    to what it meets at its own time T with the hit marked in T's colour, over the moving
    spheres where they are at T0 (filled) and T1 (outlined) (motion blur, FOCG 13.4.5)."""
    import matplotlib

    shown, ax = _axes(scene.at(scene.sampling.shutter[0]), view, ax)
    shutter_open, shutter_close = scene.sampling.shutter
    colours = matplotlib.colormaps[TIME_COLORS]
    ends, everything = [], []
    for row, col in pixels:
        origins, directions, _, times = sample_rays(scene, row, col)
        hits = cast(scene, origins, directions, times=times)
        hit = hits.index >= 0
        end = point_at(origins, directions, np.where(hit, hits.t, 2 * scene.camera.focus))
        _rays(ax, shown, origins, end, "0.55", f"rays-pixel-{row}-{col}")
        spread = max(shutter_close - shutter_open, 1e-12)
        ax.scatter(*shown.project(end[hit]).T, s=18, zorder=6,
                   color=colours((times[hit] - shutter_open) / spread))  # fmt: skip
        ends.append(end)
        everything.append(origins)
    moving = np.flatnonzero(np.any(scene.velocities[: len(scene.spheres)] != 0, axis=1))
    for i in moving:
        sphere = scene.at(shutter_close).spheres[i]
        _outline(ax, shown, sphere.center, sphere.radius, colours(1.0))
    ax.set_title(f"each ray at its own time T in [{shutter_open:g}, {shutter_close:g}]")
    finish_axes(ax, shown, np.vstack([*ends, *everything, _spheres(scene)]), scene.camera)
    return ax.figure


def _axes(scene: Scene, view: str, ax: Axes | None) -> tuple[View, Axes]:
    """A top, side or front view of ``scene`` with its objects drawn."""
    shown = view_for(scene.camera, view)
    if shown.is_3d:
        raise ValueError("the sampled rays are drawn in a top, side or front view, not in 3D")
    ax = new_axes(shown, ax, size=(7, 5))
    draw_scene_objects(ax, shown, scene)
    return shown, ax


def _spheres(scene: Scene) -> np.ndarray:
    """The corners ``(2S, 3)`` of the spheres' boxes: what a diagram must show whole."""
    centres = np.array([s.center for s in scene.spheres], dtype=float).reshape(-1, 3)
    radii = np.array([s.radius for s in scene.spheres], dtype=float)[:, None]
    return np.vstack([centres - radii, centres + radii])


def _rays(ax: Axes, view: View, starts: np.ndarray, ends: np.ndarray, colors, gid: str) -> None:
    segments = np.stack([starts, ends], axis=1)
    draw_lines(ax, view, segments, gid, colors=colors, linewidths=1.1, zorder=4)


def _outline(ax: Axes, view: View, center: np.ndarray, radius: float, color) -> None:
    ax.add_patch(Circle(view.project(center), radius, facecolor="none", edgecolor=color, lw=2,
                        linestyle="dashed", zorder=5))  # fmt: skip

"""A scene's rays: from the eye (or the orthographic eye plane) to what they hit, and on.

The rays and hit points are the renderer's own (:func:`raykit.render.cast_pixels`), so the ray
drawn through pixel (r, c) ends on the object that pixel of the render shows. Hits are drawn
solid in the colour of what they hit; misses dashed and faded, to the edge of the picture.

In a lit scene or one with mirrors, the secondary rays that shading casts for those pixels are
drawn too, as shading cast them (:class:`RecordingCaster` wraps the caster that
:func:`raykit.shading.shade` is given, so the physics knows nothing of diagrams): shadow rays
thin and gold up to their light, or dark red up to what blocks them (marked x); mirror rays
silver, to what they meet (dashed when they meet nothing).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from raykit.camera import image_plane_corners
from raykit.diagrams.labels import clear_label
from raykit.diagrams.views import (
    draw_lines,
    draw_outline,
    draw_scene_objects,
    finish_axes,
    new_axes,
    view_for,
)
from raykit.lights import PointLight
from raykit.rays import length, point_at
from raykit.render import cast_pixels, secondary_caster
from raykit.scene import Scene
from raykit.shading import needs_shading, shade
from raykit.shadows import Caster

MOST_RAYS_A_SIDE = 8


@dataclass(frozen=True)
class RaySegments:
    """Secondary rays that shading cast: ``kind`` ("shadow" or "mirror"), ``origins``,
    ``directions`` ``(M, 3)``, where each ends ``t (M,)`` (inf: nothing met) and ``blocked
    (M,)`` (shadow rays stopped before their light)."""

    kind: str
    origins: np.ndarray
    directions: np.ndarray
    t: np.ndarray
    blocked: np.ndarray


class RecordingCaster:
    """A caster that casts with ``cast`` and keeps every call's rays as :class:`RaySegments`:
    a call with ``t_max`` is a shadow test (blocked where the nearest hit is nearer than its
    light, :func:`raykit.shadows.in_shadow`), one without is a mirror bounce."""

    def __init__(self, cast: Caster) -> None:
        self.cast = cast
        self.segments: list[RaySegments] = []

    def __call__(self, origins: np.ndarray, directions: np.ndarray, t_max=None):
        if t_max is None:
            hits = self.cast(origins, directions)
            blocked = np.zeros(len(origins), dtype=bool)
            self.segments.append(RaySegments("mirror", origins, directions, hits.t, blocked))
        else:
            hits = self.cast(origins, directions, t_max)
            t = np.minimum(hits.t, t_max)
            self.segments.append(
                RaySegments("shadow", origins, np.asarray(directions), t, hits.t < t_max)
            )
        return hits


def chosen_pixels(
    width: int,
    height: int,
    every: int | None = None,
    row: int | None = None,
    pixels: list[tuple[int, int]] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(rows, cols) ``(N,)`` of the pixels whose rays to draw: the given ``pixels``; else every
    k-th pixel of ``row``; else every k-th pixel in both directions, centred in the image.
    k defaults to a value that draws at most 8 rays a side."""
    if pixels is not None:
        rows, cols = np.array(pixels, dtype=int).reshape(-1, 2).T
        return rows, cols
    every = every or max(1, math.ceil(max(width, height) / MOST_RAYS_A_SIDE))
    cols = np.arange((width - 1) % every // 2, width, every)
    if row is not None:
        return np.full(len(cols), row), cols
    rows = np.arange((height - 1) % every // 2, height, every)
    grid_rows, grid_cols = np.meshgrid(rows, cols, indexing="ij")
    return grid_rows.ravel(), grid_cols.ravel()


def ray_diagram(
    scene: Scene,
    *,
    view: str = "3d",
    every: int | None = None,
    row: int | None = None,
    pixels: list[tuple[int, int]] | None = None,
    ax: Axes | None = None,
) -> Figure:
    """Draw ``scene`` and the primary rays of the chosen pixels (see :func:`chosen_pixels`).

    ``view``: "3d" (3D axes), "top" or "side" (2D projections, see
    :mod:`raykit.diagrams.views`). ``ax`` must be 3D axes for the 3D view. Returns the figure.
    """
    camera = scene.camera
    shown = view_for(camera, view)
    ax = new_axes(shown, ax)
    rows, cols = chosen_pixels(camera.width, camera.height, every, row, pixels)
    origins, directions, hits = cast_pixels(scene, rows, cols)
    ends = point_at(origins, directions, hits.t)
    hit = hits.index >= 0
    paths: list[RaySegments] = []
    if needs_shading(scene):
        recorder = RecordingCaster(secondary_caster(scene))
        shade(scene, recorder, origins, directions, hits)
        paths = recorder.segments

    corners = image_plane_corners(camera)
    extent = _scene_points(scene, corners)
    reach = float(length(np.ptp(np.vstack([extent, ends[hit]]), axis=0)))
    draw_scene_objects(ax, shown, scene)
    _draw_secondary(ax, shown, paths, reach)
    draw_lines(
        ax,
        shown,
        np.stack([origins[hit], ends[hit]], axis=1),
        gid="rays-hit",
        colors=np.clip(hits.color[hit], 0, 1),
        linewidths=1.2,
        zorder=4,
    )
    misses = np.stack([origins[~hit], origins[~hit] + reach * directions[~hit]], axis=1)
    draw_lines(
        ax,
        shown,
        misses,
        gid="rays-missed",
        colors="0.5",
        linewidths=0.8,
        linestyles=(0, (4, 3)),
        alpha=0.6,
        zorder=1,
    )
    draw_outline(ax, shown, corners, colors="black", linewidths=1.0, zorder=5)
    _mark(ax, shown, camera.eye, "eye")
    for light in scene.lights:
        if isinstance(light, PointLight):
            _mark(ax, shown, light.position, "light", marker="*")
    if shown.is_3d:
        _mark(ax, shown, corners[1], "image plane", marker=None)
        ax.scatter(*shown.project(ends[hit]).T, color="black", s=4, depthshade=False)
    else:
        ax.plot(*shown.project(ends[hit]).T, "o", color="black", ms=2, zorder=6)
    title = f"{len(rows)} rays through pixel centres ({int(hit.sum())} hit): solid = hit, "
    title += "dashed = miss"
    if not shown.is_3d:
        # named here, not beside the outline: there a name crosses the rays or leaves the axes
        title += ";\nthe black outline across the rays: the image plane"
    if paths:
        shadow = sum(len(p.t) for p in paths if p.kind == "shadow")
        blocked = sum(int(p.blocked.sum()) for p in paths if p.kind == "shadow")
        mirror = sum(len(p.t) for p in paths if p.kind == "mirror")
        title += f"\n{shadow} shadow rays ({blocked} blocked, x), {mirror} mirror rays"
    ax.set_title(title, fontsize=10)
    # after the title, which it may add to
    finish_axes(ax, shown, np.vstack([extent, ends[hit]]), camera)
    return ax.figure


SECONDARY_STYLE = {
    "shadow": {"colors": "goldenrod", "linewidths": 0.7, "linestyles": (0, (1, 2))},
    "blocked": {"colors": "darkred", "linewidths": 0.9},
    "mirror": {"colors": "silver", "linewidths": 1.2},
    "mirror-missed": {"colors": "silver", "linewidths": 0.8, "linestyles": (0, (4, 3))},
}


def _draw_secondary(ax: Axes, view, paths: list[RaySegments], reach: float) -> None:
    """The recorded shadow and mirror rays; a ray that meets nothing is drawn ``reach`` long."""
    for kind in ("shadow", "mirror"):
        segments = [p for p in paths if p.kind == kind]
        if not segments:
            continue
        origins = np.vstack([p.origins for p in segments])
        directions = np.vstack([p.directions for p in segments])
        t = np.concatenate([p.t for p in segments])
        blocked = np.concatenate([p.blocked for p in segments])
        ends = origins + np.minimum(t, reach)[:, None] * directions
        missed = np.isinf(t) & (kind == "mirror")
        styles = ((kind, ~blocked & ~missed), ("blocked", blocked), ("mirror-missed", missed))
        for style, rows in styles:
            if rows.any():
                lines = np.stack([origins[rows], ends[rows]], axis=1)
                draw_lines(ax, view, lines, gid=f"rays-{style}", zorder=3, **SECONDARY_STYLE[style])
        if blocked.any():
            marks = view.project(ends[blocked])
            if view.is_3d:
                ax.scatter(*marks.T, marker="x", color="darkred", s=14, depthshade=False)
            else:
                ax.plot(*marks.T, "x", color="darkred", ms=4, zorder=6)


def _scene_points(scene: Scene, corners: np.ndarray) -> np.ndarray:
    """Points ``(N, 3)`` that the picture must hold: eye, image plane, objects."""
    points = [np.asarray(scene.camera.eye, float)[None], corners]
    points += [light.position[None] for light in scene.lights if isinstance(light, PointLight)]
    for sphere in scene.spheres:
        points.append(sphere.center + np.array([[-1, -1, -1], [1, 1, 1]]) * sphere.radius)
    for billboard in scene.billboards:
        ul = np.asarray(billboard.upper_left, float)
        points.append(
            np.stack([ul, ul + billboard.a, ul + billboard.b, ul + billboard.a + billboard.b])
        )
    return np.vstack(points)


def _mark(ax: Axes, view, point: np.ndarray, label: str, marker: str | None = "o") -> None:
    shown = view.project(point)
    if marker:
        ax.plot(*[[c] for c in shown], marker, color="black", ms=5, zorder=7)
    clear_label(ax, shown, label, fontsize=10)

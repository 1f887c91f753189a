"""The camera of the conventions in :mod:`raykit.camera`, drawn: e, lookat, up, the u, v, w
frame, the frustum to the image plane, a coarse pixel grid with its centres, d and fov_angle.

Points come from the camera's own functions (:func:`raykit.camera.image_plane_points`,
:func:`raykit.camera.rays_through`) on a coarse copy of the camera, so the grid is readable
while the geometry is exactly the camera's.
"""

from __future__ import annotations

from dataclasses import replace

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from raykit.camera import Camera, image_plane_corners, image_plane_points, pixel_points
from raykit.diagrams.labels import clear_label
from raykit.diagrams.views import draw_lines, draw_outline, fewer_ticks_3d, view_for
from raykit.rays import normalize

COARSE_COLUMNS = 8
UP_LENGTH = 1.5  # up's arrow, as a multiple of u, v and w's: apart from v even when they agree


def coarse(camera: Camera, columns: int = COARSE_COLUMNS) -> Camera:
    """The camera with at most ``columns`` pixel columns and rows in the same aspect ratio."""
    width = min(camera.width, columns)
    height = max(1, round(width * camera.height / camera.width))
    return replace(camera, width=width, height=height)


def camera_diagram(camera: Camera, *, ax: Axes | None = None) -> Figure:
    """One camera in 3D axes (``ax`` must be 3D if given). Returns the figure."""
    if ax is None:
        ax = plt.figure(figsize=(6, 6), layout="constrained").add_subplot(projection="3d")
    view = view_for(camera, "3d")
    grid = coarse(camera)
    u, v, w = camera.frame
    eye, lookat = np.asarray(camera.eye, float), np.asarray(camera.lookat, float)
    d = camera.d
    x_edges, y_edges = np.arange(grid.width + 1), np.arange(grid.height + 1)

    # the image plane: its pixel grid lines and the pixel centres
    lines = [image_plane_points(grid, np.full(2, x), np.array([0, grid.height])) for x in x_edges]
    lines += [image_plane_points(grid, np.array([0, grid.width]), np.full(2, y)) for y in y_edges]
    draw_lines(ax, view, np.stack(lines), colors="0.35", linewidths=0.7)
    centres = image_plane_points(grid, *pixel_points(grid.width, range(grid.height)))
    ax.scatter(*view.project(centres).T, color="black", s=6, depthshade=False)

    # the frustum: the eye to the plane's corners, or the parallel rays of the orthographic view
    corners = image_plane_corners(grid)
    if camera.projection == "orthographic":
        starts = corners + d * w  # the eye plane: eye + s·u + t·v
        draw_outline(ax, view, starts, colors="0.5", linewidths=0.8, linestyles="dashed")
    else:
        starts = np.broadcast_to(eye, corners.shape)
    draw_lines(ax, view, np.stack([starts, corners], axis=1), colors="0.5", linewidths=0.8)

    # the frame at the eye, up, and d along -w to lookat. up is often close to v (it need only
    # lie in the plane of v and w), so it is drawn longer than v. Every label is placed where
    # it crosses no line, marker or other label (raykit.diagrams.labels), near what it names
    # (arrows at least 0.15 of the drawing: at a wide fov_angle the plane dwarfs d)
    extent = np.ptp(np.vstack([eye[None], corners, starts]), axis=0).max()
    size = max(0.35 * d, 0.15 * extent)
    for vector, label, color, length in (
        (u, "u", "tab:red", 1.0),
        (v, "v", "tab:green", 1.0),
        (w, "w", "tab:blue", 1.0),
        (normalize(np.asarray(camera.up, float)), "up", "0.4", UP_LENGTH),
    ):
        tip = eye + length * size * vector
        draw_lines(ax, view, np.stack([eye, tip])[None], colors=color, linewidths=2)
        clear_label(ax, view.project(tip), label, color=color, fontsize=12, fontweight="bold")
    draw_lines(
        ax, view, np.stack([eye, lookat])[None], colors="black", linewidths=1, linestyles="dotted"
    )
    ax.scatter(*view.project(np.stack([eye, lookat])).T, color="black", s=18, depthshade=False)
    clear_label(ax, view.project(eye), "e", toward=-45, fontsize=12)
    clear_label(ax, view.project(lookat), "lookat", toward=-135, fontsize=11)
    clear_label(ax, view.project((eye + lookat) / 2), "d", toward=-45, fontsize=12, style="italic")

    if camera.projection == "perspective":  # fov_angle: from the top edge to the bottom edge
        Hp = camera.plane_size[1]
        edge = lookat + Hp / 2 * v
        draw_lines(ax, view, np.stack([eye, edge])[None], colors="black", linewidths=0.8)
        # the arc between the top edge and the bottom one, nearer the eye than d's label
        angles = np.linspace(-camera.fov_angle / 2, camera.fov_angle / 2, 25)
        radius = 0.3 * d
        arc = eye + radius * (
            np.cos(np.radians(angles))[:, None] * -w + np.sin(np.radians(angles))[:, None] * v
        )
        ax.plot(*view.project(arc).T, color="black", lw=1)
        clear_label(ax, view.project(arc[-1]), "fov_angle", toward=150, fontsize=11)

    up = normalize(np.asarray(camera.up, float))
    points = np.vstack(
        [eye[None], corners, starts, eye + size * np.stack([u, v, w, UP_LENGTH * up])]
    )
    shown = view.project(points)
    centre = (shown.min(axis=0) + shown.max(axis=0)) / 2
    half = (shown.max(axis=0) - shown.min(axis=0)).max() / 2 * 1.05
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=18, azim=-62)
    # draw in zorder, not by depth: the labels are placed after the lines and markers are drawn
    ax.computed_zorder = False
    # no gridlines across the box, where the labels are set: the ticks give the coordinates
    ax.grid(False)
    ax.set_title(
        f"{camera.projection}: {camera.width} x {camera.height} pixels\n"
        f"(drawn {grid.width} x {grid.height}), fov_angle = {camera.fov_angle:g}°",
        fontsize=11,
    )
    for label, axis in zip((ax.set_xlabel, ax.set_ylabel, ax.set_zlabel), view.axes, strict=True):
        label("xyz"[axis])
    fewer_ticks_3d(ax)
    return ax.figure


def camera_diagrams(camera: Camera) -> Figure:
    """The camera as perspective and as orthographic, side by side."""
    figure = plt.figure(figsize=(11, 5.5), layout="constrained")
    for k, projection in enumerate(("perspective", "orthographic")):
        ax = figure.add_subplot(1, 2, k + 1, projection="3d")
        camera_diagram(replace(camera, projection=projection), ax=ax)
    return figure

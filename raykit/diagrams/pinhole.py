"""The camera obscura beside the pinhole camera, drawn from the renderer's own rays.

:func:`pinhole_figure`: a side view (depth along -w, height along v, through the image's middle
column) of the rays of a few pixel rows: each leaves the obscura's back wall, crosses at the hole
e, passes the pinhole camera's image plane in front and ends where :func:`raykit.render.cast`
says it hits; below, the picture on the back wall (:func:`raykit.pinhole.render_obscura`:
upside down and mirrored) beside the pinhole render (:func:`raykit.render.render`: upright).
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from raykit.camera import rays_through
from raykit.io.images import quantize
from raykit.pinhole import obscura_rays, render_obscura
from raykit.rays import dot, point_at
from raykit.render import cast, render
from raykit.scene import Scene

ROWS_DRAWN = 9


def pinhole_figure(scene: Scene) -> Figure:
    """Three panels: the side view of both cameras' rays, the obscura's wall picture and the
    pinhole render of ``scene`` (a perspective camera). Returns the figure."""
    camera = scene.camera
    figure = plt.figure(figsize=(10, 7.2), layout="constrained")
    grid = figure.add_gridspec(2, 2, height_ratios=[1.15, 1])
    side = figure.add_subplot(grid[0, :])
    u, v, w = camera.frame
    eye, d = np.asarray(camera.eye, float), camera.d

    def local(points: np.ndarray) -> np.ndarray:  # (depth in front of the eye, height)
        relative = points - eye
        return np.column_stack([-dot(relative, w), dot(relative, v)])

    rows = np.linspace(0.5, camera.height - 0.5, ROWS_DRAWN)
    x = np.full(ROWS_DRAWN, camera.width / 2)
    origins, directions = rays_through(camera, x, rows)
    hits = cast(scene, origins, directions)
    # the wall pixel turned half a turn from (x, row) sends its obscura ray the same way
    _, back = obscura_rays(camera, camera.width - x, camera.height - rows)
    wall = eye - back * (d / -dot(back, w))[:, None]  # where that ray left the wall
    front = origins + directions * (d / -dot(directions, w))[:, None]
    ends = np.where(
        np.isfinite(hits.t)[:, None],
        point_at(origins, directions, hits.t),
        origins + 1.6 * d * directions,
    )
    for k in range(ROWS_DRAWN):
        color = hits.color[k]
        path = local(np.stack([wall[k], eye, ends[k]]))
        side.plot(*path.T, color=color, lw=1.6, ls="-" if np.isfinite(hits.t[k]) else "--")
        if np.isfinite(hits.t[k]) and hits.t[k] < d / -dot(directions[k], w):
            # it hits before the image plane (the plane cuts through that object): the same
            # ray goes on, dotted, to its dot on the plane
            beyond = local(np.stack([ends[k], front[k]]))
            side.plot(*beyond.T, color=color, lw=1.2, ls=":")
        side.plot(*local(front[k : k + 1]).T, "o", color=color, ms=5)
        side.plot(*local(wall[k : k + 1]).T, "s", color=color, ms=6)
    limits = local(np.vstack([wall, ends, front]))
    top, bottom = limits[:, 1].max(), limits[:, 1].min()
    # the walls' names in a band above every ray, each on its own side of its line
    band = 0.3 * (top - bottom)
    side.set_ylim(bottom - 0.08 * (top - bottom), top + band)
    for depth, label, dx, align in (
        (-d, "back wall\n(camera obscura)", 6, "left"),
        (d, "image plane\n(pinhole camera)", -6, "right"),
    ):
        side.axvline(depth, color="0.3", lw=2)
        side.annotate(
            label,
            (depth, top + band),
            xytext=(dx, -3),
            textcoords="offset points",
            ha=align,
            va="top",
            fontsize=10,
        )
    side.plot(0, 0, "ko", ms=7)
    side.annotate("hole e", (0, 0), xytext=(-10, -16), textcoords="offset points", fontsize=10)
    side.annotate(
        "",
        (-0.35 * d, 0.8 * bottom),
        (0, 0.8 * bottom),
        arrowprops=dict(arrowstyle="-|>", color="0.4"),
    )
    side.annotate("w", (-0.35 * d, 0.8 * bottom), xytext=(-12, -4), textcoords="offset points")
    side.set_xlabel("depth in front of the hole, along -w")
    side.set_ylabel("height along v")
    side.set_title(
        f"{ROWS_DRAWN} rows of the middle column: each ray crosses at the hole,\nso the top of "
        "the scene lands at the bottom of the wall (dotted: a ray on past its hit)",
        fontsize=10,
    )
    obscura = render_obscura(scene).color.reshape(camera.height, camera.width, 3)
    for column, (image, title) in enumerate(
        (
            (obscura, "on the back wall: upside down and mirrored"),
            (render(scene).rgb, "the pinhole camera's image plane: upright"),
        )
    ):
        ax = figure.add_subplot(grid[1, column])
        ax.imshow(quantize(image))
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(title, fontsize=10)
    return figure

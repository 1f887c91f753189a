"""Ray diagrams of the line-scan world: the slide's picture, drawn from the tracer's own rays.

:func:`ray_diagram` draws the world from above, to scale: the eye e, the u and w arrows, the
image line at distance D with its pixel centres and the scan's colours on it, the fov angle,
the objects, and the rays, each from its origin to the hit point the tracer returned, in the
colour of what it hit (solid), or faded and dashed to the edge of the frame where it hits
nothing; beside it, the scan as a strip of pixels. :func:`sweep_diagram` shows the world at a
few scan times above the sweep image as far as it has grown.

Nothing here computes geometry of its own: rays and hits come from
:mod:`raykit.linescan.scan`. Figures stay readable in grey: misses are dashed, objects outlined.
Conventions: :mod:`raykit.linescan.camera`.
"""

from __future__ import annotations

import math

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Arc, Circle

from raykit.linescan.camera import pixel_positions
from raykit.linescan.scan import Scan, scan, sweep
from raykit.linescan.scene import LineScene
from raykit.textures import OPAQUE_FROM

MAX_RAYS_DRAWN = 24


def _frame_limits(scene: LineScene, hits: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) corners ``(2,)`` of the frame: around the camera, its image line and the
    hit points, with room for the objects near them (a long wall is cut at the frame)."""
    cam = scene.camera
    u, w = cam.frame
    half = 1.0 if cam.projection == "perspective" else cam.width / 2
    line_centre = cam.e + (cam.D * w if cam.projection == "perspective" else 0)
    core = [np.asarray(cam.e, float)[None], line_centre + np.outer([-half, half], u)]
    found = hits[np.isfinite(hits).all(axis=1)]
    if len(found):
        core.append(found)
    core = np.concatenate(core)
    lower, upper = core.min(axis=0), core.max(axis=0)
    reach = max(upper - lower) * 0.6 + 1.0  # objects this far outside still show in full
    extra = []
    for ball in scene.balls:
        extra.append(ball.center + np.array([[-1, -1], [1, 1]]) * ball.radius)
    for billboard in scene.billboards:
        extra.append(np.stack([billboard.start, billboard.end]))
    for points in extra:
        near = points[((points > lower - reach) & (points < upper + reach)).all(axis=1)]
        if len(near) == len(points):
            lower, upper = np.minimum(lower, near.min(axis=0)), np.maximum(upper, near.max(axis=0))
    pad = 0.08 * max(upper - lower) + 0.2
    return lower - pad, upper + pad


def _exit_points(origins: np.ndarray, directions: np.ndarray, lower, upper) -> np.ndarray:
    """Where rays leave the frame [lower, upper] (slab method), ``(N, 2)``: where misses end."""
    with np.errstate(divide="ignore", invalid="ignore"):
        t_lower = (lower - origins) / directions
        t_upper = (upper - origins) / directions
    t_exit = np.nanmin(np.where(directions != 0, np.maximum(t_lower, t_upper), np.inf), axis=1)
    return origins + t_exit[:, None] * directions


def _draw_objects(ax: Axes, scene: LineScene) -> None:
    for ball in scene.balls:
        ax.add_patch(
            Circle(
                ball.center, ball.radius, facecolor=ball.color, edgecolor="black", lw=1.0, zorder=3
            )
        )
    for billboard in scene.billboards:
        if billboard.texture is None:
            colors = np.asarray(billboard.color, float)[None]
        else:
            rgba = billboard.texture.rgba[billboard.row]
            opaque = rgba[:, 3:] >= OPAQUE_FROM
            colors = np.where(opaque, rgba[:, :3] / 255.0, 1.0)  # holes drawn white
        ends = np.linspace(0.0, 1.0, len(colors) + 1)[:, None]
        points = billboard.start + ends * (billboard.end - billboard.start)
        segments = np.stack([points[:-1], points[1:]], axis=1)
        ax.plot(
            *np.stack([billboard.start, billboard.end]).T,
            color="black",
            lw=7,
            solid_capstyle="butt",
            zorder=3,
        )
        ax.add_collection(
            LineCollection(segments, colors=colors, linewidths=5, zorder=4, capstyle="butt")
        )


def _draw_camera(ax: Axes, scene: LineScene, taken: Scan, annotate: bool) -> None:
    cam = scene.camera
    e = np.asarray(cam.e, float)
    u, w = cam.frame
    ax.plot(*e, "ko", ms=5, zorder=6)
    ax.annotate("e", e - 0.3 * w, fontsize=11, ha="center", va="center")
    for vector, label in ((w, "w"), (u, "u")) if annotate else ():
        ax.annotate(
            "", e + vector, e, arrowprops=dict(arrowstyle="-|>", color="black", lw=1.3), zorder=6
        )
        ax.annotate(
            label, e + 1.2 * vector, fontsize=11, ha="center", va="center", fontweight="bold"
        )
    if cam.projection == "perspective":
        half, line_centre, centres = 1.0, e + cam.D * w, pixel_positions(cam)
    else:
        half, line_centre, centres = cam.width / 2, e, taken.origins
    ends = line_centre + np.outer([-half, half], u)
    cells = np.linspace(-half, half, cam.pixels + 1)[:, None] * u + line_centre
    ax.plot(*ends.T, color="black", lw=5.5, solid_capstyle="butt", zorder=4)
    ax.add_collection(
        LineCollection(
            np.stack([cells[:-1], cells[1:]], axis=1),
            colors=np.clip(taken.colors, 0, 1),
            linewidths=4,
            zorder=5,
            capstyle="butt",
        )
    )
    if cam.pixels <= 64:
        ax.plot(*centres.T, "o", color="white", mec="black", ms=2.5, mew=0.6, zorder=6)
    if not annotate:
        return
    ax.annotate("image line", ends[1] + 0.25 * u, fontsize=9, ha="center", va="center")
    for i, end in ((0, ends[0]), (cam.pixels - 1, ends[1])):
        ax.annotate(f"i={i}", end + 0.3 * w, fontsize=8, ha="center", va="center")
    if cam.projection == "perspective":
        side = -0.35 * u  # the D dimension line, set off to the right of w
        ax.annotate(
            "", line_centre + side, e + side, arrowprops=dict(arrowstyle="<->", color="0.25", lw=1)
        )
        ax.annotate(
            "D",
            e + side + 0.5 * cam.D * w - 0.18 * u,
            fontsize=11,
            ha="center",
            va="center",
            style="italic",
        )
        heading = math.degrees(math.atan2(w[1], w[0]))
        radius = 0.45 * cam.D
        ax.add_patch(
            Arc(
                e,
                2 * radius,
                2 * radius,
                angle=heading,
                theta1=-cam.fov_angle / 2,
                theta2=cam.fov_angle / 2,
                color="0.25",
                lw=1,
            )
        )
        edge = math.radians(heading + cam.fov_angle / 2)
        ax.annotate(
            f"fov_angle = {cam.fov_angle:g}°",
            e + 1.1 * radius * np.array([math.cos(edge), math.sin(edge)]),
            fontsize=9,
            ha="right",
            va="bottom",
        )


def _draw_rays(ax: Axes, scene: LineScene, taken: Scan, every: int, lower, upper) -> None:
    chosen = np.arange(0, scene.camera.pixels, every)
    hit = chosen[taken.index[chosen] >= 0]
    missed = chosen[taken.index[chosen] < 0]
    ends = taken.hit_points[hit]
    rays = LineCollection(
        np.stack([taken.origins[hit], ends], axis=1),
        colors=np.clip(taken.colors[hit], 0, 1),
        linewidths=1.2,
        zorder=2,
    )
    rays.set_gid("rays-hit")
    ax.add_collection(rays)
    ax.plot(*ends.T, "o", color="black", ms=2.5, zorder=5)
    exits = _exit_points(taken.origins[missed], taken.directions[missed], lower, upper)
    misses = LineCollection(
        np.stack([taken.origins[missed], exits], axis=1),
        colors="0.55",
        linewidths=0.9,
        linestyles=(0, (4, 3)),
        alpha=0.6,
        zorder=1,
    )
    misses.set_gid("rays-missed")
    ax.add_collection(misses)


def _draw_strip(ax: Axes, taken: Scan, every: int) -> None:
    pixels = len(taken.colors)
    ax.imshow(
        np.clip(taken.colors, 0, 1)[None],
        aspect="auto",
        interpolation="nearest",
        extent=(-0.5, pixels - 0.5, 0, 1),
    )
    for i in range(pixels + 1):
        ax.axvline(i - 0.5, color="black", lw=0.4 if pixels <= 64 else 0)
    ticks = np.arange(0, pixels, every)
    ax.set_xticks(ticks)
    ax.set_yticks([])
    ax.set_xlabel("pixel i (the scan)")


def ray_diagram(
    scene: LineScene,
    *,
    every: int | None = None,
    ax: Axes | None = None,
    strip_ax: Axes | None = None,
    title: str | None = None,
    annotate: bool = True,
    frame: tuple[np.ndarray, np.ndarray] | None = None,
) -> Figure:
    """The slide's ray diagram of one scan of ``scene``, with the scan strip below it.

    ``every``: draw the ray of every k-th pixel (default: at most 24 rays). ``ax``: draw the
    world there; ``strip_ax``: draw the strip there (with ``ax`` given and no ``strip_ax``, the
    strip is left out). ``annotate=False`` leaves out the labels (u, w, D, fov_angle), for small
    panels. ``frame``: the (lower, upper) corners to show, instead of a frame fitted to this
    scan (the sweep diagram gives all its panels one frame). Returns the figure.
    """
    taken = scan(scene)
    pixels = scene.camera.pixels
    every = every or max(1, math.ceil(pixels / MAX_RAYS_DRAWN))
    if ax is None:
        fig, (ax, strip_ax) = plt.subplots(
            2, 1, figsize=(7, 7.6), gridspec_kw={"height_ratios": [12, 1]}, layout="constrained"
        )
    lower, upper = _frame_limits(scene, taken.hit_points) if frame is None else frame
    _draw_rays(ax, scene, taken, every, lower, upper)
    _draw_objects(ax, scene)
    _draw_camera(ax, scene, taken, annotate)
    ax.set_xlim(lower[0], upper[0])
    ax.set_ylim(lower[1], upper[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    drawn = len(range(0, pixels, every))
    ax.set_title(
        title or f"{pixels} pixels, {drawn} rays drawn: solid = hit, dashed = miss", fontsize=10
    )
    if strip_ax is not None:
        _draw_strip(strip_ax, taken, every)
    return ax.figure


def sweep_diagram(
    scene: LineScene, *, times: tuple[int, ...] | None = None, scans: int | None = None
) -> Figure:
    """The world at a few scan times (top) above the sweep image grown up to each (bottom)."""
    count = scene.scans if scans is None else scans
    times = times or tuple(int(round(f * (count - 1))) for f in (0.2, 0.5, 0.8))
    image = np.clip(sweep(scene, count).image, 0, 1)
    fig, axes = plt.subplots(
        2,
        len(times),
        figsize=(3.8 * len(times), 8),
        gridspec_kw={"height_ratios": [1, 1.1]},
        layout="constrained",
    )
    axes = np.asarray(axes).reshape(2, len(times))
    # one frame for every panel, around all of them: the camera does not seem to jump
    corners = [_frame_limits(scene.at(m), scan(scene.at(m)).hit_points) for m in times]
    frame = (np.min([c[0] for c in corners], axis=0), np.max([c[1] for c in corners], axis=0))
    for column, m in enumerate(times):
        ray_diagram(
            scene.at(m), ax=axes[0, column], title=f"scan m = {m}", annotate=False, frame=frame
        )
        grown = image.copy()
        grown[m + 1 :] = 1.0  # not taken yet
        bottom = axes[1, column]
        bottom.imshow(grown, aspect="auto", interpolation="nearest")
        bottom.axhline(m, color="black", lw=1, ls="--")
        bottom.set_xlabel("pixel i")
        bottom.set_ylabel("scan m")
    return fig

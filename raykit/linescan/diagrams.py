"""Ray diagrams of the line-scan world: the slide's picture, drawn from the tracer's own rays.

:func:`ray_diagram` draws the world from above, to scale: the eye e, the u and w arrows, the
image line at distance D with its pixel centres and the scan's colours on it, the fov angle,
the objects, and the rays, each from its origin to the hit point the tracer returned, in the
colour of what it hit (solid), or faded and dashed to the edge of the frame where it hits
nothing; beside it, the scan as a strip of pixels. :func:`sweep_diagram` shows the world at a
few scan times above the sweep image as far as it has grown. :func:`paths_of_light` draws
photons leaving a light, most of them never reaching the image. :func:`pixel_formulas` sets the
slide's second pixel formula, u_i = i·2/N_cols, i = 0, ±1, ±2, …, ±N_cols/2, beside the pixel
centres x_i that the cameras use.

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

from raykit.billboards import OPAQUE_FROM
from raykit.diagrams.labels import DISTANCES, arrow, clear_label
from raykit.linescan.camera import pixel_positions, pixel_x, slide_pixel_positions
from raykit.linescan.scan import Scan, scan, sweep, trace
from raykit.linescan.scene import LineScene
from raykit.rays import dot, length

MAX_RAYS_DRAWN = 24
# the characters of pixel numbers the scan strip's width holds side by side (24 two-digit
# ones): a scan of hundreds of pixels labels every other tick, its numbers being longer
STRIP_LABEL_CHARACTERS = 48
# where the fov_angle label may go: a wide fov_angle's rays fill the frame in front of the eye,
# and its label, the longest, may find room only further off, behind the eye
FAR = (*DISTANCES, 8.5, 10.0, 11.5, 13.0, 15.0, 17.0, 19.5, 22.0)


def _frame_limits(scene: LineScene, hits: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(lower, upper) corners ``(2,)`` of the frame: around the camera, its image line and the
    hit points, with room for the objects near them (a long wall is cut at the frame)."""
    cam = scene.camera
    u, w = cam.frame
    e = np.asarray(cam.e, float)
    half = 1.0 if cam.projection == "perspective" else cam.width / 2
    line_centre = e + (cam.D * w if cam.projection == "perspective" else 0)
    # the eye, its u and w arrows (a wide fov_angle puts the image line nearer than w's tip)
    core = [np.stack([e, e + w, e + u, e - u]), line_centre + np.outer([-half, half], u)]
    found = hits[np.isfinite(hits).all(axis=1)]
    if len(found):
        core.append(found)
    # what the camera looks at, hit or not (a wide fov_angle's few rays may miss it all)
    core += [p[None] for p in _object_points(scene) if _in_view(cam, e, u, w, p)]
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


def _object_points(scene: LineScene) -> list[np.ndarray]:
    """Each ball's centre, each billboard's ends and middle, ``(2,)`` each."""
    points = [np.asarray(ball.center, float) for ball in scene.balls]
    for billboard in scene.billboards:
        start, end = np.asarray(billboard.start, float), np.asarray(billboard.end, float)
        points += [start, end, (start + end) / 2]
    return points


def _in_view(cam, e: np.ndarray, u: np.ndarray, w: np.ndarray, point: np.ndarray) -> bool:
    """Whether ``point`` is in front of the camera, inside its fov_angle (perspective) or its
    width (orthographic)."""
    ahead, across = dot(point - e, w), dot(point - e, u)
    if ahead <= 0:
        return False
    if cam.projection == "perspective":
        return abs(across) <= ahead * math.tan(math.radians(cam.fov_angle) / 2)
    return abs(across) <= cam.width / 2


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
    behind = _degrees(-w)  # the eye's side away from the rays: where labels find room
    ax.plot(*e, "ko", ms=5, zorder=6)
    clear_label(ax, e, "e", toward=behind, fontsize=11)
    for vector, label in ((w, "w"), (u, "u")) if annotate else ():
        arrow(ax, e, e + vector, arrowstyle="-|>", color="black", lw=1.3, zorder=6)
        clear_label(ax, e + vector, label, toward=_degrees(vector), fontsize=11, fontweight="bold")
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
    # past the line's end along u; the first and last pixel's i beside the ends, on the eye's
    # side of the line, where no ray has fanned out yet
    clear_label(ax, ends[1] + 0.3 * u, "image line", toward=_degrees(u), fontsize=10)
    for i, end in ((0, ends[0]), (cam.pixels - 1, ends[1])):
        clear_label(ax, end, f"i={i}", toward=behind, fontsize=10)
    if cam.projection == "perspective":
        heading = math.degrees(math.atan2(w[1], w[0]))
        radius = 0.45 * cam.D
        # over the rays, which hid it under them
        ax.add_patch(
            Arc(
                e,
                2 * radius,
                2 * radius,
                angle=heading,
                theta1=-cam.fov_angle / 2,
                theta2=cam.fov_angle / 2,
                color="black",
                lw=1.6,
                zorder=6,
            )
        )
        # off the rays, or further off where a wide fov_angle's rays leave no room near; before
        # D, which then keeps off its leader (the two share the room beside the eye)
        edge = math.radians(heading + cam.fov_angle / 2)
        clear_label(
            ax,
            e + radius * np.array([math.cos(edge), math.sin(edge)]),
            f"fov_angle = {cam.fov_angle:g}°",
            toward=_degrees(u),
            distances=FAR,
            fontsize=10,
        )
        side = -0.35 * u  # the D dimension line, set off to the right of w
        arrow(ax, e + side, line_centre + side, arrowstyle="<->", color="0.25", lw=1)
        clear_label(
            ax, e + side + 0.5 * cam.D * w, "D", toward=_degrees(-u), fontsize=11, style="italic"
        )


def _degrees(vector: np.ndarray) -> float:
    """The direction of a 2D ``vector``, in degrees counterclockwise from +x."""
    return math.degrees(math.atan2(vector[1], vector[0]))


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
    ticks = np.arange(0, pixels, every)  # under the drawn rays' pixels
    step = math.ceil(len(ticks) * len(str(ticks[-1])) / STRIP_LABEL_CHARACTERS)
    ax.set_xticks(ticks[::step])
    ax.set_xticks(ticks, minor=True)
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


# the slide's own TeX, set by matplotlib's mathtext, with the kit's N for its N_cols
SLIDE_FORMULA = (
    r"$u_i = i \cdot 2/N_{cols}, \quad i = 0, \pm 1, \pm 2, \dots, \pm N_{cols}/2$:"
    r" the slide, with $N_{cols} = N$"
)


def pixel_formulas(counts: tuple[int, ...] = (8, 7), ax: Axes | None = None) -> Figure:
    """The image line from -1 to 1 cut into N pixels, once per N in ``counts``: the centres
    x_i = -1 + (i + 0.5)·2/N (:func:`raykit.linescan.camera.pixel_x`, what raykit uses) as
    dots, and the slide's u_i = i·2/N_cols, i = 0, ±1, ±2, …, ±N_cols/2 for N_cols = N
    (:func:`raykit.linescan.camera.slide_pixel_positions`) as crosses, each row counted."""
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 1.1 + 0.9 * len(counts)), layout="constrained")
    for row, n in enumerate(counts):
        y = -1.4 * row
        edges = np.linspace(-1, 1, n + 1)
        for left, right, shade in zip(edges[:-1], edges[1:], range(n), strict=True):
            ax.fill_between([left, right], y - 0.3, y + 0.3, color=("0.93", "0.82")[shade % 2])
        centres, slide = pixel_x(n), slide_pixel_positions(n)
        ax.plot(
            centres,
            np.full(n, y),
            "o",
            color="tab:blue",
            ms=7,
            label=r"$x_i = -1 + (i + 0.5) \cdot 2/N$: the pixel centres" if row == 0 else None,
        )
        ax.plot(
            slide,
            np.full(len(slide), y),
            "x",
            color="tab:red",
            ms=10,
            mew=2.2,
            label=SLIDE_FORMULA if row == 0 else None,
        )
        ax.text(
            1.08, y, f"N = {n}: {n} centres, {len(slide)} slide positions", va="center", fontsize=10
        )
    ax.axvline(-1, color="black", lw=1)
    ax.axvline(1, color="black", lw=1)
    ax.set_xlim(-1.1, 2.05)
    ax.set_ylim(-1.4 * (len(counts) - 1) - 0.6, 0.9)
    ax.set_yticks([])
    ax.set_xticks([-1, -0.5, 0, 0.5, 1])
    ax.set_xlabel("position on the image line (u)")
    # under the axes: over them it lay on the image line's ends
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.35), fontsize=10, ncol=1, frameon=False)
    for side in ("top", "right", "left"):
        ax.spines[side].set_visible(False)
    ax.set_title("the slide's second pixel formula against the pixel centres", fontsize=10)
    return ax.figure


def paths_of_light(
    scene: LineScene,
    light: tuple[float, float],
    photons: int = 90,
    seed: int = 0,
    ax: Axes | None = None,
) -> Figure:
    """Photons leaving a point ``light`` (2,) in random directions (seeded), each to the first
    thing it meets (the tracer's own :func:`raykit.linescan.scan.trace`). A photon *arrives* if
    the camera sees the point it lit (the eye's ray toward it meets the same object there,
    within the field of view): drawn solid, with its bounce to the eye; the rest faded, misses
    dashed to the frame's edge. Returns the figure."""
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 6), layout="constrained")
    camera = scene.camera
    u, w = camera.frame
    e = np.asarray(camera.e, float)
    rng = np.random.default_rng(seed)
    angles = rng.uniform(0, 2 * np.pi, photons)
    directions = np.column_stack([np.cos(angles), np.sin(angles)])
    origins = np.broadcast_to(np.asarray(light, float), directions.shape).copy()
    hits = trace(scene, origins, directions)
    hit = np.isfinite(hits.t)
    points = origins + np.where(hit, hits.t, 0.0)[:, None] * directions
    to_point = points - e
    distance = length(to_point)
    with np.errstate(invalid="ignore", divide="ignore"):
        seen = trace(scene, np.broadcast_to(e, points.shape).copy(), to_point / distance[:, None])
        inside = dot(to_point, w) / distance >= math.cos(math.radians(camera.fov_angle) / 2)
    arrives = hit & inside & (seen.index == hits.index)
    arrives &= np.abs(seen.t - distance) <= 1e-9 * (distance + 1)
    lower = np.minimum(e, np.asarray(light)) - 1.5
    upper = np.maximum(e, np.asarray(light)) + 1.5
    for obj in scene.balls:
        lower = np.minimum(lower, obj.center - obj.radius - 0.5)
        upper = np.maximum(upper, obj.center + obj.radius + 0.5)
    ends = np.where(hit[:, None], points, _exit_points(origins, directions, lower, upper))
    # the faded photons drawn from a little way out: the light's name needs a clear ring
    clear = 0.06 * length(upper - lower)
    starts = origins + np.minimum(clear, 0.5 * length(ends - origins))[:, None] * directions
    for k in np.flatnonzero(~arrives):
        ax.plot(
            *np.stack([starts[k], ends[k]]).T,
            color="goldenrod",
            alpha=0.35,
            lw=0.8,
            ls="-" if hit[k] else "--",
            zorder=1,
        )
    for k in np.flatnonzero(arrives):
        ax.plot(*np.stack([origins[k], points[k], e]).T, color="darkorange", lw=1.6, zorder=5)
        ax.plot(*points[k], "o", color="darkorange", ms=4, zorder=6)
    _draw_objects(ax, scene)
    half = math.radians(camera.fov_angle) / 2
    for sign in (-1, 1):  # the field of view's edges, and the image line
        edge = w * math.cos(half) + sign * u * math.sin(half)
        ax.plot(*np.stack([e, e + 2.2 * camera.D * edge]).T, color="0.5", lw=0.8, ls=":")
    line = np.stack([e + camera.D * w - u, e + camera.D * w + u])
    ax.plot(*line.T, color="black", lw=3)
    ax.plot(*e, "ko", ms=6)
    clear_label(ax, e, "eye e", toward=_degrees(-w))
    ax.plot(*light, "*", color="gold", mec="black", ms=18, zorder=7)
    clear_label(ax, light, "light", toward=45)
    ax.set_xlim(lower[0], upper[0])
    ax.set_ylim(lower[1], upper[1])
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(
        f"{photons} photons from the light: {int(hit.sum())} hit something, "
        f"{int(arrives.sum())} bounce into the camera (solid);\nthe rest never reach the image",
        fontsize=10,
    )
    return ax.figure

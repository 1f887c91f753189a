"""Views for 3D diagrams: drawing scene objects on 3D axes or on a top, side or front projection.

A *view* maps world points ``(N, 3)`` to what an axes plots, by picking and ordering world axes.
The world axis closest to the camera's ``up`` is "up"; of the other two, the one closest to the
view direction is "depth", the last "across". The 3D view plots (across, depth, up), so that up
is matplotlib's vertical axis; the top view plots (across, depth), looking down the up axis;
the side view plots (depth, up); the front view plots (across, up), looking along the depth
axis as the eye does. In the example scenes (y up, looking along -z) that is (x, z), (z, y) and
(x, y). The depth axis is flipped where needed so that the eye is at the bottom of the top view
and on the left of the side view, looking into the picture, and the across axis so that the
front view's right is the eye's; axes are labelled.
"""

from __future__ import annotations

from dataclasses import dataclass

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.patches import Circle, Polygon
from matplotlib.transforms import Affine2D
from mpl_toolkits.mplot3d.art3d import Line3DCollection

from raykit.billboards import OPAQUE_FROM
from raykit.camera import Camera
from raykit.rays import length
from raykit.scene import Scene

VIEWS = ("3d", "top", "side", "front")
AXIS_NAMES = "xyz"


@dataclass(frozen=True)
class View:
    """Which world axes a view plots, in order: three for 3D axes, two for a projection."""

    name: str
    axes: tuple[int, ...]

    @property
    def is_3d(self) -> bool:
        return len(self.axes) == 3

    def project(self, points: np.ndarray) -> np.ndarray:
        """World points ``(..., 3)`` as plotted ``(..., 3)`` or ``(..., 2)``."""
        return np.asarray(points, float)[..., list(self.axes)]


def view_for(camera: Camera, name: str) -> View:
    """The view ``name`` ("3d", "top", "side" or "front") of a scene seen by ``camera``."""
    if name not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(VIEWS)}, got {name!r}")
    up = int(np.argmax(np.abs(camera.up)))
    view_direction = np.abs(np.asarray(camera.lookat, float) - camera.eye)
    view_direction[up] = -1
    depth = int(np.argmax(view_direction))
    across = 3 - up - depth
    axes = {"3d": (across, depth, up), "top": (across, depth), "side": (depth, up),
            "front": (across, up)}[name]  # fmt: skip
    return View(name, axes)


def new_axes(view: View, ax: Axes | None, size: tuple[float, float] = (7, 6)) -> Axes:
    """``ax`` if given (it must be 3D for the 3D view), else a new figure's axes."""
    if ax is not None:
        return ax
    figure = plt.figure(figsize=size, layout="constrained")
    return figure.add_subplot(projection="3d" if view.is_3d else None)


def finish_axes(ax: Axes, view: View, points: np.ndarray, camera: Camera) -> None:
    """Equal aspect around ``points (N, 3)``, labelled axes, depth increasing towards the eye."""
    shown = view.project(points)
    lower, upper = np.nanmin(shown, axis=0), np.nanmax(shown, axis=0)
    centre, half = (lower + upper) / 2, max(upper - lower) / 2 * 1.08 + 1e-9
    if view.is_3d:
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(centre[2] - half, centre[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.set_xlabel(AXIS_NAMES[view.axes[0]])
        ax.set_ylabel(AXIS_NAMES[view.axes[1]])
        ax.set_zlabel(AXIS_NAMES[view.axes[2]])
        fewer_ticks_3d(ax)
        ax.grid(False)  # gridlines would cross the box where its labels are set; ticks stay
        eye, lookat = view.project(camera.eye), view.project(camera.lookat)
        if eye[1] > lookat[1]:  # depth grows away from the viewer of the 3D box
            ax.invert_yaxis()
        return
    pad = 0.05 * max(upper - lower) + 1e-9
    ax.set_xlim(lower[0] - pad, upper[0] + pad)
    ax.set_ylim(lower[1] - pad, upper[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel(AXIS_NAMES[view.axes[0]])
    ax.set_ylabel(AXIS_NAMES[view.axes[1]])
    eye = view.project(camera.eye)
    lookat = view.project(camera.lookat)
    for k, flip in ((0, ax.invert_xaxis), (1, ax.invert_yaxis)):
        # keep the eye on the left (side view) / at the bottom (top view) of the picture
        if view.name == "side" and k == 0 and eye[0] > lookat[0]:
            flip()
        if view.name == "top" and k == 1 and eye[1] > lookat[1]:
            flip()
        if view.name == "front" and k == 0 and _right(camera)[view.axes[0]] < 0:
            flip()


def _right(camera: Camera) -> np.ndarray:
    """The eye's right ``(3,)``: the direction of view crossed with up (the camera's u)."""
    return np.cross(np.asarray(camera.lookat, float) - camera.eye, np.asarray(camera.up, float))


def fewer_ticks_3d(ax: Axes) -> None:
    """At most five ticks an axis of 3D axes (the depth axis, foreshortened, ran its numbers
    into each other with more); an axis far from 0 numbers no ticks, and the title says where
    it is (matplotlib's offset text, "+1e6", lay on the tick labels; in the axis label it ran
    off the figure). Call after the limits, labels and title are set."""
    from matplotlib.ticker import MaxNLocator, NullFormatter

    far = []
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(nbins=4))
        low, high = sorted(axis.get_view_interval())
        centre = (low + high) / 2
        if abs(centre) > 1000 * (high - low):
            axis.set_major_formatter(NullFormatter())
            far.append(f"{axis.get_label_text()} near {centre:.1e}")
    if far:
        title = ax.get_title()
        where = ", ".join(far)
        ax.set_title(f"{title}\n{where}" if title else where, fontsize=ax.title.get_fontsize())


def draw_lines(ax: Axes, view: View, segments: np.ndarray, gid: str | None = None, **style):
    """Line segments ``(N, 2, 3)`` in world coordinates, as one collection."""
    shown = view.project(segments)
    collection = Line3DCollection(shown, **style) if view.is_3d else LineCollection(shown, **style)
    if gid:
        collection.set_gid(gid)
    if view.is_3d:
        ax.add_collection3d(collection)
    else:
        ax.add_collection(collection)
    return collection


def draw_outline(ax: Axes, view: View, corners: np.ndarray, **style):
    """A closed polygon through world points ``corners (N, 3)``."""
    return draw_lines(ax, view, np.stack([corners, np.roll(corners, -1, axis=0)], axis=1), **style)


def draw_scene_objects(ax: Axes, view: View, scene: Scene) -> None:
    """Billboards (their textures), then spheres (shaded balls in 3D, outlined discs in 2D)."""
    for billboard in scene.billboards:
        _draw_billboard(ax, view, billboard)
    for sphere in scene.spheres:
        if view.is_3d:
            lat, lon = np.mgrid[0 : np.pi : 13j, 0 : 2 * np.pi : 25j]
            unit = np.stack([np.sin(lat) * np.cos(lon), np.sin(lat) * np.sin(lon), np.cos(lat)])
            surface = view.project(np.moveaxis(unit, 0, -1) * sphere.radius + sphere.center)
            ax.plot_surface(
                *np.moveaxis(surface, -1, 0),
                color=sphere.color,
                alpha=0.55,
                linewidth=0.2,
                edgecolor="0.3",
                shade=True,
            )
        else:
            ax.add_patch(
                Circle(
                    view.project(sphere.center),
                    sphere.radius,
                    facecolor=sphere.color,
                    edgecolor="black",
                    lw=0.8,
                    alpha=0.85,
                    zorder=2,
                )
            )


def _billboard_texels(billboard, most: int = 48) -> np.ndarray:
    """The billboard's look as float RGBA ``(H, W, 4)``, at most ``most`` texels a side."""
    if billboard.texture is None:
        return np.concatenate([np.asarray(billboard.color, float), [1.0]])[None, None]
    rgba = billboard.texture.rgba
    step = max(1, int(np.ceil(max(rgba.shape[:2]) / most)))
    texels = rgba[::step, ::step] / 255.0
    texels[..., 3] = np.where(rgba[::step, ::step, 3] >= OPAQUE_FROM, 0.95, 0.0)  # holes stay holes
    return texels


def _draw_billboard(ax: Axes, view: View, billboard) -> None:
    texels = _billboard_texels(billboard)
    rows, cols = texels.shape[:2]
    ul, a, b = np.asarray(billboard.upper_left, float), billboard.a, billboard.b
    corners = np.stack([ul, ul + a, ul + a + b, ul + b])
    if view.is_3d:
        alpha, beta = np.meshgrid(np.linspace(0, 1, cols + 1), np.linspace(0, 1, rows + 1))
        grid = view.project(ul + alpha[..., None] * a + beta[..., None] * b)
        ax.plot_surface(
            *np.moveaxis(grid, -1, 0),
            facecolors=texels,
            rstride=1,
            cstride=1,
            shade=False,
            linewidth=0,
        )
        ax.plot(*view.project(np.vstack([corners, corners[:1]])).T, color="black", lw=0.8)
        return
    shown = view.project(corners)
    ax.add_patch(Polygon(shown, closed=True, fill=False, edgecolor="black", lw=1.0, zorder=3))
    p0, pa, pb = shown[0], shown[1] - shown[0], shown[3] - shown[0]
    if abs(pa[0] * pb[1] - pa[1] * pb[0]) < 1e-12 * (length(pa) * length(pb)):
        return  # seen edge-on: the outline is all there is to see
    # texel (col, row) -> ul + (col/W) a + (row/H) b, projected: an affine map
    to_world = Affine2D(
        np.array(
            [[pa[0] / cols, pb[0] / rows, p0[0]], [pa[1] / cols, pb[1] / rows, p0[1]], [0, 0, 1]]
        )
    )
    ax.imshow(
        texels,
        extent=(0, cols, rows, 0),
        interpolation="nearest",
        alpha=0.5,
        transform=to_world + ax.transData,
        zorder=1,
    )  # faded: rays and balls stay clear

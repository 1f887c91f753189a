"""Labels that sit beside what they name, never on a ray, an edge, a marker or another label.

A label made by :func:`clear_label` is placed each time its axes are drawn, after their lines,
patches and markers (and a 3D box's edges and gridlines) and before their texts: at the size
the figure is drawn at, it takes the first place round its point, nearest first and its
preferred side first, whose box crosses none of them (as :mod:`raykit.io.legibility` measures
them), nor the leader of a label placed before it, and lies inside the axes; a label sent far
off gets a leader line, which runs through no other label. So a diagram's
labels stay clear whatever the scene, and wherever the figure is shrunk or stored at more dpi.

A log axis's tick labels keep apart by :func:`decade_ticks`: powers of ten only, at least two
of them in view, whatever range measured data (timings, errors) gives the axis.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.patches import FancyArrowPatch
from matplotlib.text import Annotation, Text
from matplotlib.ticker import LogLocator, NullFormatter
from matplotlib.transforms import IdentityTransform

from raykit.io.legibility import box_edges_3d, drawing_of, segments_cross

# how far from its point a label may go, in multiples of its font size, nearest first
DISTANCES = (0.3, 0.7, 1.2, 1.9, 2.8, 4.0, 5.5, 7.5)
DIRECTIONS = 16  # tried round the point at each distance, the preferred one first
CLEARANCE_PX = 3.0  # room kept between a label and the lines and markers round it
UNDER = 3.0  # _cost's least for something under a label's box (a line in the room round it: 1)
LEADER_FROM = 1.5  # a label further from its point than this (font sizes) gets a leader line
# a leader through another label, either way round, costs as much as a label off the axes: a
# label with lines under it, which a back row still reads, is better than one struck through
LEADER_ON_LABEL = 100.0


def clear_label(
    ax: Axes,
    point,
    text: str,
    toward: float = 45.0,
    distances: tuple[float, ...] = DISTANCES,
    **style,
) -> Annotation:
    """Label ``point`` (its data coordinates: 2 numbers, or 3 in 3D axes) with ``text``, placed
    at each draw where nothing of ``ax`` is under it, ``toward`` (degrees, counterclockwise
    from the right) preferred, ``distances`` from the point tried (in font sizes, nearest
    first). ``style``: Text properties (fontsize, color, ...)."""
    label = ax.annotate(
        text,
        (0.0, 0.0),
        xycoords=IdentityTransform(),
        xytext=(0.0, 0.0),
        textcoords="offset pixels",
        ha="center",
        va="center",
        annotation_clip=False,
        # a leader to the point, shown only when the label had to go far from it
        arrowprops={"arrowstyle": "-", "color": "0.45", "lw": 0.7, "shrinkA": 1, "shrinkB": 2},
        **style,
    )
    label.set_in_layout(False)  # inside the axes by placement: no part of the layout's room
    _placer(ax).labels.append((label, np.asarray(point, float), toward, distances))
    return label


def arrow(ax: Axes, start, end, **style) -> FancyArrowPatch:
    """An arrow from ``start`` to ``end`` (data coordinates) drawn as one of ``ax``'s patches,
    so that labels are placed off it (an annotation's own arrow is not: it is part of a label).
    ``style``: FancyArrowPatch properties (arrowstyle, color, lw, ...)."""
    patch = FancyArrowPatch(
        tuple(start), tuple(end), mutation_scale=10, shrinkA=0, shrinkB=0, **style
    )
    ax.add_patch(patch)
    return patch


def decade_ticks(ax: Axes) -> None:
    """Label ``ax``'s log axes at powers of ten only, at least two in view, so that their tick
    labels keep apart whatever range the data gives them. Where the view holds fewer than two
    powers of ten, matplotlib labels the minor ticks too (2 x 10^-2, 3 x 10^-2, ...), which ran
    into each other on a figure fitted to a projector; here such a view, when the axes
    autoscale, is widened out to whole decades, and no minor tick is labelled. The powers of
    ten are thinned as matplotlib thins them, to as many as the axis has room for. Call it after
    the axes are made log (``loglog``, ``set_xscale("log")`` reset the ticks)."""
    for axis in (ax.xaxis, ax.yaxis):
        if axis.get_scale() == "log":
            axis.set_major_locator(_Decades())
            axis.set_minor_formatter(NullFormatter())


class _Decades(LogLocator):
    """Ticks at the powers of ten; an autoscaled view with fewer than two of them in it widened
    out to whole decades."""

    def __init__(self) -> None:
        super().__init__(base=10.0, subs=(1.0,), numticks="auto")

    def view_limits(self, vmin: float, vmax: float) -> tuple[float, float]:
        vmin, vmax = super().view_limits(vmin, vmax)
        low, high = math.log10(vmin), math.log10(vmax)
        if math.floor(high) - math.ceil(low) + 1 >= 2:
            return vmin, vmax
        return 10.0 ** math.floor(low), 10.0 ** max(math.ceil(high), math.floor(low) + 1)


def _placer(ax: Axes) -> _Placer:
    for artist in ax.artists:
        if isinstance(artist, _Placer):
            return artist
    placer = _Placer(ax)
    ax.add_artist(placer)
    return placer


class _Placer(Artist):
    """Drawn after the axes' lines, patches and markers (zorder 2) and before their texts (3):
    places the axes' clear labels where those lines are drawn now."""

    def __init__(self, ax: Axes) -> None:
        super().__init__()
        self.ax = ax
        self.labels: list[tuple[Annotation, np.ndarray, float, tuple[float, ...]]] = []
        self.set_zorder(2.99)

    def draw(self, renderer) -> None:
        drawings = drawing_of(self.ax) + box_edges_3d(self.ax)
        segments = np.concatenate([d.segments for d in drawings] + [np.zeros((0, 2, 2))])
        points = np.concatenate([d.points for d in drawings] + [np.zeros((0, 2))])
        # each marker's half width, and room to spare round it
        reach = np.concatenate(
            [np.full(len(d.points), d.marker_px + CLEARANCE_PX) for d in drawings] + [np.zeros(0)]
        )
        areas = [d.area for d in drawings if d.area is not None]
        ours = {id(label) for label, *_ in self.labels}
        taken = [
            _box(t, renderer)
            for t in self.ax.texts
            if id(t) not in ours and t.get_visible() and t.get_text().strip()
        ]
        inside = self.ax.bbox
        leaders = np.zeros((0, 2, 2))  # of the labels placed so far
        for label, point, toward, distances in self.labels:
            anchor = self._display(point)
            label.xy = tuple(anchor)
            label.set_position((0.0, 0.0))
            label.update_positions(renderer)  # its transform follows the new point
            box = _box(label, renderer)
            half = np.array([box[2] - box[0], box[3] - box[1]]) / 2
            size = renderer.points_to_pixels(label.get_fontsize())
            # the best place at DISTANCES; where something lies under its box there (a line
            # across it, another label, the axes' edge), the best clear one further off, if
            # the label may go there (``distances`` beyond DISTANCES) and its leader crosses less
            best, best_cost, best_under, far = None, math.inf, math.inf, False
            further, further_cost = None, math.inf
            for (dx, dy), distance in _candidates(toward, size, half, distances):
                centre = anchor + (dx, dy)
                rect = (*(centre - half), *(centre + half))
                under = _cost(rect, segments, points, reach, areas, taken, inside)
                room = (rect[0] - CLEARANCE_PX, rect[1] - CLEARANCE_PX)
                room += (rect[2] + CLEARANCE_PX, rect[3] + CLEARANCE_PX)
                under += LEADER_ON_LABEL * float(np.count_nonzero(segments_cross(leaders, room)))
                cost = under
                if distance > LEADER_FROM:  # its leader: over no other label, few lines
                    leader = np.array([[anchor, centre]])
                    cost += LEADER_ON_LABEL * sum(
                        bool(segments_cross(leader, box)[0]) for box in taken
                    )
                    cost += 0.2 * float(np.count_nonzero(_crossings(leader[0], segments)))
                if distance > DISTANCES[-1]:
                    if under == 0 and cost < further_cost:
                        further, further_cost = (dx, dy), cost
                elif cost < best_cost:
                    best, best_cost, best_under = (dx, dy), cost, under
                    far = distance > LEADER_FROM
                if cost == 0:
                    break
            if best_under >= UNDER and further_cost < best_cost:
                best, far = further, True
            label.set_position(best)
            label.update_positions(renderer)
            label.arrow_patch.set_visible(far)
            taken.append(_box(label, renderer))
            if far:  # its leader, which the labels after it keep off
                leaders = np.concatenate([leaders, [[anchor, anchor + best]]])

    def _display(self, point: np.ndarray) -> np.ndarray:
        if len(point) == 3:  # 3D axes: the point as their projection now shows it
            from mpl_toolkits.mplot3d import proj3d

            x, y, _ = proj3d.proj_transform(*point, self.ax.get_proj())
            point = np.array([x, y])
        return self.ax.transData.transform(point[:2])


def _box(text: Text, renderer) -> tuple[float, float, float, float]:
    box = Text.get_window_extent(text, renderer)  # an annotation's text, not its arrow
    return (box.x0, box.y0, box.x1, box.y1)


def _candidates(toward: float, size: float, half: np.ndarray, distances=DISTANCES):
    """Offsets (display pixels) of a label's centre from its point: round it at each of
    ``distances`` (font sizes), ``toward`` first, then alternately either side of it."""
    turns = [0] + [s * k for k in range(1, DIRECTIONS // 2 + 1) for s in (1, -1)][: DIRECTIONS - 1]
    for distance in distances:
        for turn in turns:
            angle = math.radians(toward + turn * 360 / DIRECTIONS)
            u = np.array([math.cos(angle), math.sin(angle)])
            # the box's edge, not its centre, at this distance: a box reaches |u.x| w/2 + ...
            reach = distance * size + abs(u[0]) * half[0] + abs(u[1]) * half[1]
            yield tuple(u * reach), distance


def _cost(rect, segments, points, reach, areas, taken, inside) -> float:
    """0 for a clear place; otherwise how much is under the label there (lines and markers
    crossed, other labels covered, the axes' edge crossed count most)."""
    cost = 0.0
    if rect[0] < inside.x0 or rect[1] < inside.y0 or rect[2] > inside.x1 or rect[3] > inside.y1:
        cost += 100
    grown = (
        rect[0] - CLEARANCE_PX,
        rect[1] - CLEARANCE_PX,
        rect[2] + CLEARANCE_PX,
        rect[3] + CLEARANCE_PX,
    )
    # a line in the room round the label costs less than one under it
    cost += float(np.count_nonzero(segments_cross(segments, grown)))
    cost += 3.0 * float(np.count_nonzero(segments_cross(segments, rect)))
    near = (
        (points[:, 0] > rect[0] - reach)
        & (points[:, 0] < rect[2] + reach)
        & (points[:, 1] > rect[1] - reach)
        & (points[:, 1] < rect[3] + reach)
    )
    cost += float(np.count_nonzero(near))
    for other in taken:
        if min(rect[2], other[2]) > max(rect[0], other[0]) and min(rect[3], other[3]) > max(
            rect[1], other[1]
        ):
            cost += 10
    centre = ((rect[0] + rect[2]) / 2, (rect[1] + rect[3]) / 2)
    cost += 0.5 * sum(area.contains_point(centre) for area in areas)
    return cost


def _crossings(leader: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """Which of ``segments`` (K, 2, 2) the segment ``leader`` (2, 2) crosses."""
    if not len(segments):
        return np.zeros(0, bool)
    a, b = leader
    c, d = segments[:, 0], segments[:, 1]

    def side(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (
            r[..., 0] - p[..., 0]
        )

    return (side(a, b, c) * side(a, b, d) < 0) & (side(c, d, a) * side(c, d, b) < 0)

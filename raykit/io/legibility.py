"""Pictures a back row can read: the projector rule, and a figure's text measured as it is drawn.

The rule (docs/lecturers.md, "Figures a back row can read"): a picture projected to fill a
1920 x 1080 screen, whichever way it fits, is blown up at most 1.6 times, and its smallest text
is at least 1/40 of the screen's height there (27 px). For a picture W x H pixels whose smallest
text is t pixels high that is

    W >= 1200 or H >= 675   and   t >= max(H / 40, W / 71.1).

The size is the picture's own pixels, whatever drew it: a render's pixels are the rays it traced,
so a render is stored at that size by rendering that many pixels, never by enlarging a smaller
one. A figure's text is measured while the figure is drawn into the PNG (:func:`measuring`):
each text artist matplotlib draws, its box in the stored picture (its window extent, with the
ground behind it), and the height of its lines as the renderer lays them out. The same draw
gives the problems a :class:`Layout` lists: no text cut off at the picture's edge, no two texts
on each other, no label's leader line through another text, and no text on a drawn line, a
patch's edge or a marker (the figure's own drawing; not a 2D axes' frame, ticks and grid, which
text is laid out beside), nor a 3D axes' text on the edges and gridlines of its box, which run
through the space its labels are set in (:func:`box_edges_3d`).
"""

from __future__ import annotations

import contextlib
import json
import math
import struct
import zlib
from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np

SCREEN = (1920, 1080)
SMALLEST_SCREEN_TEXT = SCREEN[1] / 40  # 27 px
LARGEST_ENLARGEMENT = 1.6
# a box touching a line, or two texts whose boxes share a pixel's edge, do not cover each other
TOUCH_PX = 1.0
# the PNG text chunk that carries a figure's measured layout (figure_png writes it)
LAYOUT_KEY = "raykit measured layout"


def screen_scale(width: float, height: float) -> float:
    """How many times a ``width`` x ``height`` picture is blown up to fill the screen."""
    return min(SCREEN[0] / width, SCREEN[1] / height)


def size_problems(width: int, height: int) -> list[str]:
    """What keeps a ``width`` x ``height`` picture from being projected sharp; [] when nothing."""
    scale = screen_scale(width, height)
    if scale <= LARGEST_ENLARGEMENT:
        return []
    return [
        f"{width} x {height} px is blown up {scale:.2f} times to fill a {SCREEN[0]} x "
        f"{SCREEN[1]} screen (at most {LARGEST_ENLARGEMENT}: {SCREEN[0] / LARGEST_ENLARGEMENT:.0f}"
        f" px wide or {SCREEN[1] / LARGEST_ENLARGEMENT:.0f} high)"
    ]


def text_problems(width: int, height: int, text_px: float | None) -> list[str]:
    """What keeps text ``text_px`` pixels high, in a ``width`` x ``height`` picture, from being
    read when the picture is projected; [] when nothing (or no text)."""
    if text_px is None:
        return []
    scale = screen_scale(width, height)
    if text_px * scale >= SMALLEST_SCREEN_TEXT - 0.05:
        return []
    return [
        f"its smallest text, {text_px:.1f} px high, is {text_px * scale:.1f} px on the screen "
        f"(at least {SMALLEST_SCREEN_TEXT:.0f}: {max(height / 40, width / 71.1):.1f} px here)"
    ]


def legibility_problems(width: int, height: int, text_px: float | None) -> list[str]:
    """The rule above for a stored picture: its size, and its smallest text (None: no text)."""
    return size_problems(width, height) + text_problems(width, height, text_px)


@dataclass(frozen=True)
class DrawnText:
    """A text as drawn: ``box`` (x0, y0, x1, y1) in the stored picture's pixels, y down, with
    the ground drawn behind it; ``height_px``, the height of its lines as laid out."""

    text: str
    box: tuple[float, float, float, float]
    height_px: float


@dataclass(frozen=True)
class DrawnImage:
    """An image (imshow) as drawn: its array's ``pixels`` (columns, rows) and its ``box`` in the
    stored picture's pixels, y down."""

    pixels: tuple[int, int]
    box: tuple[float, float, float, float]


@dataclass
class Layout:
    """What one draw of a figure put into the picture: its ``size`` (width, height) in pixels,
    its texts and images, and the problems :func:`measuring` found in them."""

    size: tuple[int, int] = (0, 0)
    texts: list[DrawnText] = field(default_factory=list)
    images: list[DrawnImage] = field(default_factory=list)
    problems: list[str] = field(default_factory=list)

    @property
    def smallest_text_px(self) -> float | None:
        return min((t.height_px for t in self.texts), default=None)

    def to_json(self) -> str:
        return json.dumps(
            {
                "size": list(self.size),
                "texts": [
                    [t.text, [round(v, 1) for v in t.box], round(t.height_px, 2)]
                    for t in self.texts
                ],
                "images": [[list(i.pixels), [round(v, 1) for v in i.box]] for i in self.images],
                "problems": self.problems,
            },
            ensure_ascii=True,
        )

    @classmethod
    def from_json(cls, text: str) -> Layout:
        record = json.loads(text)
        return cls(
            size=tuple(record["size"]),
            texts=[DrawnText(t, tuple(box), h) for t, box, h in record["texts"]],
            images=[DrawnImage(tuple(p), tuple(box)) for p, box in record["images"]],
            problems=list(record["problems"]),
        )


@contextlib.contextmanager
def measuring(figure) -> Iterator[Layout]:
    """Within the block, every draw of ``figure`` measures what it draws into the yielded
    :class:`Layout` (the last draw's: savefig may draw twice, the second time into the PNG)."""
    from matplotlib.artist import Artist
    from matplotlib.text import Text

    layout = Layout()
    drawn: list[tuple[Text, object, float]] = []  # a text, its box, its line height
    text_draw = Text.draw

    def recording_draw(text, renderer):
        result = text_draw(text, renderer)
        if text.get_visible() and text.get_text().strip() and text.figure is not None:
            drawn.append((text, _footprint(text, renderer), _line_height(text, renderer)))
        return result

    class Measure(Artist):
        """Drawn after every other artist of the figure: the draw is complete."""

        def draw(self, renderer):
            measured = _measure(figure, renderer, drawn)
            layout.size, layout.texts, layout.images, layout.problems = measured
            drawn.clear()

    measure = Measure()
    measure.set_zorder(math.inf)
    figure.add_artist(measure)
    Text.draw = recording_draw
    try:
        yield layout
    finally:
        Text.draw = text_draw
        measure.remove()


def _footprint(text, renderer):
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox

    box = Text.get_window_extent(text, renderer)  # an annotation's own: without its arrow
    patch = text.get_bbox_patch()
    if patch is not None and patch.get_visible():
        box = Bbox.union([box, patch.get_window_extent(renderer)])
    return box


def _line_height(text, renderer) -> float:
    """The height of the text's shortest line as the renderer lays it out: each line set alone
    in the text's font, as matplotlib sets a line (ascender to descender)."""
    from matplotlib.text import Text

    heights = []
    for line in text.get_text().split("\n"):
        if line.strip():
            probe = Text(0, 0, line, fontproperties=text.get_fontproperties())
            probe.set_usetex(text.get_usetex())
            probe.set_parse_math(text.get_parse_math())
            probe.set_figure(text.figure)
            heights.append(probe.get_window_extent(renderer).height)
    return min(heights)


def _measure(figure, renderer, drawn):
    width, height = int(round(renderer.width)), int(round(renderer.height))

    def down(box) -> tuple[float, float, float, float]:
        return (float(box.x0), float(height - box.y1), float(box.x1), float(height - box.y0))

    legends = [a.get_legend() for a in figure.axes] + list(figure.legends)
    legends = [g for g in legends if g is not None and g.get_visible()]
    in_legend = {id(t) for g in legends for t in g.get_texts()} | {
        id(g.get_title()) for g in legends
    }
    texts = [
        DrawnText(_short(t.get_text()), down(box), h)
        for t, box, h in drawn
        if id(t) not in in_legend
    ]
    # a legend is one label: its frame, which hides whatever it lies on
    labels = [(t.text, t.box) for t in texts] + [
        ("the legend", down(g.get_window_extent(renderer))) for g in legends
    ]
    texts += [
        DrawnText(_short(t.get_text()), down(box), h) for t, box, h in drawn if id(t) in in_legend
    ]
    images = [
        DrawnImage(
            (int(image.get_array().shape[1]), int(image.get_array().shape[0])),
            down(image.get_window_extent(renderer)),
        )
        for ax in figure.axes
        if ax.get_visible()
        for image in ax.images
        if image.get_visible() and image.get_array() is not None
    ]
    problems = _cut(labels, width, height) + _overlaps(labels)
    problems += _leaders_through(drawn, labels, in_legend, height)
    drawings = [d for ax in figure.axes if ax.get_visible() for d in drawing_of(ax)]
    problems += _on_drawing(labels, [_flipped(d, height) for d in drawings], width, height)
    for ax in figure.axes:  # a 3D axes' own texts, set among the edges and gridlines of its box
        edges = box_edges_3d(ax) if ax.get_visible() else []
        if edges:
            own = {id(t) for t in ax.texts}
            inside = [(_short(t.get_text()), down(box)) for t, box, _ in drawn if id(t) in own]
            problems += _on_drawing(inside, [_flipped(d, height) for d in edges], width, height)
    return (width, height), texts, images, problems


def _leaders_through(drawn, labels, in_legend, height) -> list[str]:
    """A label's leader line (an annotation's visible arrow) that runs through another text."""
    from matplotlib.text import Annotation

    problems = []
    for text, box, _ in drawn:
        leader = getattr(text, "arrow_patch", None) if isinstance(text, Annotation) else None
        if leader is None or not leader.get_visible() or id(text) in in_legend:
            continue
        path = leader.get_transform().transform_path(leader.get_path())
        segments = np.concatenate(_path_segments(path) or [np.zeros((0, 2, 2))])
        segments = segments * np.array([1.0, -1.0]) + np.array([0.0, height])  # y down
        name = _short(text.get_text())
        own = (float(box.x0), float(height - box.y1), float(box.x1), float(height - box.y0))
        for other, (x0, y0, x1, y1) in labels:
            if (x0, y0, x1, y1) == own:
                continue
            # a leader touching a text's box passes beside it, as a line does (_on_drawing)
            inner = (x0 + TOUCH_PX, y0 + TOUCH_PX, x1 - TOUCH_PX, y1 - TOUCH_PX)
            if segments_cross(segments, inner).any():
                problems.append(f"the leader of {name!r} runs through {other!r}")
    return problems


def _short(text: str) -> str:
    text = " ".join(text.split())
    return text if len(text) <= 40 else text[:37] + "..."


def _cut(labels, width, height) -> list[str]:
    return [
        f"{name!r} is cut off at the picture's edge"
        for name, (x0, y0, x1, y1) in labels
        if x0 < -TOUCH_PX or y0 < -TOUCH_PX or x1 > width + TOUCH_PX or y1 > height + TOUCH_PX
    ]


def _overlaps(labels) -> list[str]:
    problems = []
    for i, (name_a, a) in enumerate(labels):
        for name_b, b in labels[i + 1 :]:
            if (
                min(a[2], b[2]) - max(a[0], b[0]) > TOUCH_PX
                and min(a[3], b[3]) - max(a[1], b[1]) > TOUCH_PX
            ):
                problems.append(f"{name_a!r} and {name_b!r} are drawn over each other")
    return problems


@dataclass(frozen=True)
class Drawing:
    """One artist's lines as drawn, in display pixels (y up): ``segments`` (K, 2, 2) and
    ``points`` (M, 2) (marker centres, ``marker_px`` the markers' half width), seen only within
    ``clip`` (x0, y0, x1, y1) if given; ``area``: the filled path (display pixels) of a patch,
    or None."""

    name: str
    segments: np.ndarray
    points: np.ndarray
    clip: tuple[float, float, float, float] | None
    area: object = None
    marker_px: float = 0.0


def drawing_of(ax) -> list[Drawing]:
    """The lines, patch edges and markers ``ax`` draws, as last drawn: its own drawing, not its
    frame, ticks or grid, nor a legend's or a text's own arrow and ground."""
    found = [_drawing(a) for a in [*ax.lines, *ax.collections, *ax.patches]]
    return [d for d in found if d is not None]


def box_edges_3d(ax) -> list[Drawing]:
    """The lines of a 3D axes' box as last drawn: its three axis lines and, with its grid on,
    its gridlines ([] for a 2D axes, or a 3D one drawn without its box). A 2D axes' frame and
    grid lie round and behind its data; a 3D box's edges and grid cross the space its labels
    are set in, and a label there keeps off them as off any other line."""
    if getattr(ax, "name", "") != "3d" or not getattr(ax, "_axis3don", True):
        return []
    found = []
    for axis, letter in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):
        if not axis.get_visible():
            continue
        found.append(_drawing(axis.line, f"the 3D box's {letter} axis"))
        if getattr(ax, "_draw_grid", True):  # Axes3D.grid's switch, which has no getter
            found.append(_drawing(axis.gridlines, f"the 3D box's {letter} gridlines"))
    return [d for d in found if d is not None]


def _drawing(artist, name: str | None = None) -> Drawing | None:
    """One artist's lines, markers and filled area as last drawn; None if it draws none."""
    from matplotlib.collections import LineCollection, PathCollection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    if not artist.get_visible() or artist.get_alpha() == 0:
        return None
    pixels_a_point = artist.figure.dpi / 72
    segments, points, area, marker_px = [], [], None, 0.0
    if isinstance(artist, Line2D):
        path = artist.get_transform().transform_path(_line_path(artist))
        if _draws_line(artist.get_linestyle(), artist.get_linewidth()):
            segments += _path_segments(path)
        if artist.get_marker() not in (None, "None", "none", "", " "):
            points.append(path.vertices)
            marker_px = artist.get_markersize() / 2 * pixels_a_point
    elif isinstance(artist, PathCollection):
        offsets = np.asarray(artist.get_offsets(), float).reshape(-1, 2)
        points.append(artist.get_offset_transform().transform(offsets))
        sizes = artist.get_sizes()  # the markers' areas, in points squared
        marker_px = float(np.sqrt(sizes.max())) / 2 * pixels_a_point if len(sizes) else 0.0
    elif isinstance(artist, LineCollection):
        if _edges_drawn(artist.get_linewidths(), artist.get_edgecolors()):
            transform = artist.get_transform()
            for segment in artist.get_segments():
                line = np.asarray(segment, float)[:, :2]
                if len(line) > 1:
                    xy = transform.transform(line)
                    segments.append(np.stack([xy[:-1], xy[1:]], axis=1))
    elif isinstance(artist, Patch):
        path = artist.get_transform().transform_path(artist.get_path())
        if _edges_drawn([artist.get_linewidth()], [artist.get_edgecolor()]):
            segments += _path_segments(path)
        if artist.get_fill() and artist.get_facecolor()[3] > 0:
            area = path
    elif _edges_drawn(
        getattr(artist, "get_linewidths", lambda: [0])(),
        getattr(artist, "get_edgecolors", lambda: [])(),
    ) and not len(getattr(artist, "get_offsets", lambda: [])()):
        transform = artist.get_transform()
        for path in artist.get_paths():
            segments += _path_segments(transform.transform_path(path))
    if not segments and not points and area is None:
        return None
    clip = None
    if artist.get_clip_on() and artist.get_clip_box() is not None:
        box = artist.get_clip_box()
        clip = (box.x0, box.y0, box.x1, box.y1)
    return Drawing(
        name or _name(artist),
        np.concatenate(segments) if segments else np.zeros((0, 2, 2)),
        np.concatenate(points) if points else np.zeros((0, 2)),
        clip,
        area,
        marker_px,
    )


def _line_path(line):
    """A line's path in its data coordinates; a 3D line's as its axes project it now (it is
    projected only as it is drawn, which may come after a label is placed)."""
    if hasattr(line, "get_data_3d"):
        from matplotlib.path import Path
        from mpl_toolkits.mplot3d import proj3d

        x, y, _ = proj3d.proj_transform(*line.get_data_3d(), line.axes.get_proj())
        return Path(np.column_stack([x, y]))
    return line.get_path()


def _name(artist) -> str:
    label = artist.get_label()
    kind = type(artist).__name__
    return kind if not label or label.startswith("_") else f"{kind} {label!r}"


def _draws_line(style, width) -> bool:
    return style not in ("None", "none", "", " ") and width > 0


def _edges_drawn(widths, colors) -> bool:
    colors = np.asarray(colors, float).reshape(-1, 4) if len(colors) else np.zeros((0, 4))
    return bool(np.any(np.asarray(widths, float) > 0) and np.any(colors[:, 3] > 0))


def _path_segments(path) -> list[np.ndarray]:
    segments = []
    for polygon in path.to_polygons(closed_only=False):
        polygon = polygon[np.all(np.isfinite(polygon), axis=1)]
        if len(polygon) > 1:
            segments.append(np.stack([polygon[:-1], polygon[1:]], axis=1))
    return segments


def _flipped(drawing: Drawing, height: float) -> Drawing:
    """``drawing`` in the stored picture's pixels, y down."""
    flip, shift = np.array([1.0, -1.0]), np.array([0.0, height])
    clip = drawing.clip
    if clip is not None:
        clip = (clip[0], height - clip[3], clip[2], height - clip[1])
    return Drawing(
        drawing.name,
        drawing.segments * flip + shift,
        drawing.points * flip + shift,
        clip,
        marker_px=drawing.marker_px,
    )


def _on_drawing(labels, drawings: list[Drawing], width, height) -> list[str]:
    problems = []
    for name, box in labels:
        # a box touching a line is beside it, not on it
        x0, y0, x1, y1 = box[0] + TOUCH_PX, box[1] + TOUCH_PX, box[2] - TOUCH_PX, box[3] - TOUCH_PX
        for drawing in drawings:
            clip = drawing.clip or (0.0, 0.0, float(width), float(height))
            rect = (max(x0, clip[0]), max(y0, clip[1]), min(x1, clip[2]), min(y1, clip[3]))
            if rect[0] >= rect[2] or rect[1] >= rect[3]:
                continue
            points = drawing.points
            inside = (
                (points[:, 0] > rect[0])
                & (points[:, 0] < rect[2])
                & (points[:, 1] > rect[1])
                & (points[:, 1] < rect[3])
            )
            if inside.any():
                problems.append(f"{name!r} is drawn on a marker of {drawing.name}")
            elif segments_cross(drawing.segments, rect).any():
                problems.append(f"{name!r} is drawn on a line of {drawing.name}")
    return problems


def segments_cross(segments: np.ndarray, rect) -> np.ndarray:
    """Which of ``segments`` (K, 2, 2) pass through the rectangle (x0, y0, x1, y1): Liang and
    Barsky's clipping, for all of them at once."""
    if not len(segments):
        return np.zeros(0, bool)
    start, delta = segments[:, 0], segments[:, 1] - segments[:, 0]
    low, high = np.zeros(len(segments)), np.ones(len(segments))
    keep = np.all(np.isfinite(segments), axis=(1, 2))
    for axis, (lo, hi) in enumerate(((rect[0], rect[2]), (rect[1], rect[3]))):
        p, q0, q1 = delta[:, axis], lo - start[:, axis], hi - start[:, axis]
        still = np.abs(p) < 1e-12
        keep &= ~still | ((q0 <= 0) & (q1 >= 0))
        with np.errstate(divide="ignore", invalid="ignore"):
            t0, t1 = q0 / p, q1 / p
        enter, leave = np.minimum(t0, t1), np.maximum(t0, t1)
        low = np.where(still, low, np.maximum(low, enter))
        high = np.where(still, high, np.minimum(high, leave))
    return keep & (low < high)


def png_with_layout(png: bytes, layout: Layout) -> bytes:
    """``png`` with ``layout`` in a text chunk (LAYOUT_KEY), before its end."""
    data = LAYOUT_KEY.encode("latin-1") + b"\0" + layout.to_json().encode("ascii")
    chunk = struct.pack(">I", len(data)) + b"tEXt" + data
    chunk += struct.pack(">I", zlib.crc32(b"tEXt" + data) & 0xFFFFFFFF)
    end = png.rindex(b"IEND") - 4  # the end chunk's length field
    return png[:end] + chunk + png[end:]


def read_layout(png: bytes) -> Layout | None:
    """The layout :func:`png_with_layout` wrote into ``png``; None if it carries none."""
    import io

    from PIL import Image

    image = Image.open(io.BytesIO(png))
    image.load()  # a text chunk after the pixels is read with them
    record = image.info.get(LAYOUT_KEY)
    return None if record is None else Layout.from_json(record)

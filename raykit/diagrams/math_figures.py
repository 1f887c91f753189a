"""The lecture's math, drawn with the functions that compute it.

* :func:`sphere_cases`: a ray and a circle (the sphere's cross-section) for the discriminant
  D = B² − 4AC < 0, = 0 and > 0, with the roots t0 ≤ t1 that
  :func:`raykit.spheres.sphere_roots` returns.
* :func:`plane_hit`: the plane through a with normal n, a ray o + t·d, and t_hit from
  :func:`raykit.planes.hit_plane`.
* :func:`dot_projection`: the dot product as a projection: r·u = |r| cos α is the length of
  the shadow that r casts on the unit vector u, α the angle between them.
* :func:`plane_sides`: points in front of, on and behind a plane, as
  :func:`raykit.planes.plane_side` sorts them, and the normal n = (p - a) × (q - a) that
  :func:`raykit.planes.normal_from_points` makes from three points, drawn at its own length.

Drawn in a 2D cross-section (k = 2): the math is the same in every dimension (raykit.rays).
Every text is at least :data:`SMALLEST_FONT` points and sits beside, not on, what it names, so
the figures read on a projector at the size they are stored.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from raykit.diagrams.labels import clear_label
from raykit.planes import hit_plane, normal_from_points, plane_side
from raykit.rays import dot, length, normalize, point_at
from raykit.spheres import sphere_roots

CENTER, RADIUS = np.array([0.0, 0.0]), 1.0
SMALLEST_FONT = 10  # points


def _arrow(ax: Axes, start, end, label: str | None = None, color="black", **text) -> None:
    ax.annotate("", end, start, arrowprops=dict(arrowstyle="-|>", color=color, lw=1.4))
    if label:
        ax.annotate(
            label,
            end,
            xytext=text.pop("offset", (5, 5)),
            textcoords="offset points",
            color=color,
            fontsize=11,
            **text,
        )


def _t_ticks(ax: Axes, o: np.ndarray, d: np.ndarray, t_last: float, color="tab:blue") -> None:
    """Ticks across the ray o + t d at t = 1, 2, ... up to ``t_last``, each numbered: with d
    drawn at its own length (t = 0 to 1), t at any point is read off the picture."""
    across = np.array([-d[1], d[0]]) / float(length(d))
    for step in range(1, int(np.floor(t_last)) + 1):
        p = o + step * d
        ax.plot(*np.stack([p - 0.08 * across, p + 0.08 * across]).T, color=color, lw=1.2)
        ax.annotate(
            f"{step}",
            p - 0.08 * across,
            xytext=(0, -3),
            textcoords="offset points",
            ha="center",
            va="top",
            color=color,
            fontsize=SMALLEST_FONT,
        )


def _ray_case(ax: Axes, height: float) -> None:
    o, d = np.array([[-2.6, height]]), np.array([[1.0, 0.0]])
    t0, t1, discriminant = sphere_roots(o, d, CENTER, RADIUS)
    ax.add_patch(Circle(CENTER, RADIUS, facecolor="0.9", edgecolor="black", lw=1.2))
    ax.plot(*CENTER, "k+", ms=8)
    ax.annotate("c", CENTER, xytext=(5, -14), textcoords="offset points", fontsize=11)
    ax.plot([o[0, 0], 2.6], [height, height], color="tab:blue", lw=1.4)
    # d at its own length (a unit vector here, so t is the distance along the ray), labelled
    # under the ray where no root's label goes
    _arrow(ax, o[0], o[0] + d[0], "d", color="tab:blue", offset=(-4, -16))
    ax.plot(*o[0], "o", color="tab:blue")
    ax.annotate("o", o[0], xytext=(-4, -16), textcoords="offset points", fontsize=11)
    roots = sorted({float(t) for t in (t0[0], t1[0]) if np.isfinite(t)})
    names = ["t0 = t1"] if len(roots) == 1 else ["t0", "t1"]
    # above the ray and away from the circle: t0's label up and left of its dot (the circle
    # climbs to the right of it), t1's up and right, a single root's straight up
    places = [(0, 10, "center")] if len(roots) == 1 else [(-6, 10, "right"), (6, 10, "left")]
    for t, name, (dx, dy, align) in zip(roots, names, places, strict=False):
        p = point_at(o, d, np.array([t]))[0]
        ax.plot(*p, "o", color="black", ms=6, zorder=5)
        ax.annotate(
            f"{name} = {t:.2f}",
            p,
            xytext=(dx, dy),
            textcoords="offset points",
            ha=align,
            va="bottom",
            fontsize=SMALLEST_FONT,
        )
    # sphere_roots returns D/4 (the stable form's Δ): the same sign as D = B² − 4AC
    sign = "< 0" if discriminant[0] < -1e-12 else "= 0" if abs(discriminant[0]) <= 1e-12 else "> 0"
    outcome = {"< 0": "no root: a miss", "= 0": "one root: grazes", "> 0": "two roots"}[sign]
    ax.set_title(f"D = B² − 4AC {sign}: {outcome}", fontsize=11)
    ax.set_xlim(-2.9, 2.9)
    ax.set_ylim(-1.5, 1.9)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])


def sphere_cases(axes: list[Axes] | None = None) -> Figure:
    """Three panels: a ray past, grazing and through a sphere, titled by the sign of the
    discriminant D = B² − 4AC, roots marked t0 ≤ t1. ``axes``: three."""
    if axes is None:
        _, axes = plt.subplots(1, 3, figsize=(10, 2.9), layout="constrained")
    for ax, height in zip(axes, (1.4, RADIUS, 0.45), strict=True):
        _ray_case(ax, height)
    return axes[0].figure


def plane_hit(ax: Axes | None = None) -> Figure:
    """The plane through a with normal n, and where the ray o + t·d meets it."""
    if ax is None:
        _, ax = plt.subplots(figsize=(5.5, 4.5), layout="constrained")
    a, n = np.array([1.5, 0.5]), np.array([-1.0, 0.35])
    n = n / length(n)
    along = np.array([n[1], -n[0]])
    a = a - 0.9 * along  # a lower point of the same plane: n's arrow clear of the ray
    o, d = np.array([[-2.0, -0.8]]), np.array([[1.0, 0.55]])
    t_hit = hit_plane(o, d, a, n)
    p = point_at(o, d, t_hit)[0]
    ax.plot(*np.stack([a - 1.5 * along, a + 2.9 * along]).T, color="black", lw=2)
    ax.annotate(
        "plane: (p - a)·n = 0",
        a - 1.4 * along,
        xytext=(8, 0),
        textcoords="offset points",
        fontsize=SMALLEST_FONT,
        va="center",
    )
    ax.plot(*a, "ks")
    ax.annotate("a", a, xytext=(6, -12), textcoords="offset points", fontsize=11)
    _arrow(ax, a, a + n, "n")  # unit length, as hit_plane takes it
    ax.plot([o[0, 0], p[0]], [o[0, 1], p[1]], color="tab:blue", lw=1.4)
    # d at its own length and the ray ticked at t = 1, 2, 3: t_hit is read off the picture
    _arrow(ax, o[0], o[0] + d[0], "d", color="tab:blue", offset=(-20, 4))
    _t_ticks(ax, o[0], d[0], float(t_hit[0]))
    ax.plot(*o[0], "o", color="tab:blue")
    ax.annotate("o", o[0], xytext=(-4, -14), textcoords="offset points", fontsize=11)
    ax.plot(*p, "o", color="black", ms=7, zorder=5)
    ax.annotate("p(t_hit)", p, xytext=(-6, 6), textcoords="offset points", ha="right", fontsize=11)
    ax.text(
        0.03,
        0.03,
        f"t_hit = ((a - o)·n) / (d·n) = {t_hit[0]:.2f}",
        transform=ax.transAxes,
        fontsize=SMALLEST_FONT,
    )
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title("ray–plane", fontsize=11)
    return ax.figure


def dot_projection(ax: Axes | None = None) -> Figure:
    """r·u = |r| cos α as the length of r's shadow on the unit vector u, α marked."""
    if ax is None:
        _, ax = plt.subplots(figsize=(5.5, 4.2), layout="constrained")
    origin = np.zeros(2)
    u = normalize(np.array([1.0, 0.25]))
    r = np.array([1.7, 1.5])
    projection = float(dot(r, u))
    shadow = projection * u
    ax.plot(*np.stack([origin - 0.3 * u, origin + 2.8 * u]).T, color="0.7", lw=1)
    ax.plot(*np.stack([origin, shadow]).T, color="0.25", lw=6, alpha=0.5, solid_capstyle="butt")
    ax.plot(*np.stack([r, shadow]).T, color="black", lw=1, ls="dashed")
    _arrow(ax, origin, r, "r", offset=(-4, 6))
    _arrow(ax, origin, u, "u (unit)", color="tab:red", offset=(-4, 7), ha="center")
    # α, the angle between r and u, as an arc at their common start
    from_u, to_r = (float(np.arctan2(vector[1], vector[0])) for vector in (u, r))
    angles = np.linspace(from_u, to_r, 30)
    ax.plot(0.45 * np.cos(angles), 0.45 * np.sin(angles), color="black", lw=1)
    middle = (from_u + to_r) / 2
    ax.text(0.58 * np.cos(middle), 0.58 * np.sin(middle), "α", fontsize=13, va="center")
    # the shadow's length under the line, clear of the bar: r·u from dot and from |r| cos α
    ax.annotate(
        "",
        shadow + 0.22 * np.array([u[1], -u[0]]),
        0.22 * np.array([u[1], -u[0]]),
        arrowprops=dict(arrowstyle="<->", color="0.25", lw=1),
    )
    ax.annotate(
        "r·u",
        0.5 * shadow + 0.22 * np.array([u[1], -u[0]]),
        xytext=(0, -8),
        textcoords="offset points",
        ha="center",
        va="top",
        fontsize=SMALLEST_FONT + 1,
    )
    cosine = float(np.cos(to_r - from_u))
    ax.text(
        0.5,
        0.04,
        f"r·u = {projection:.2f} = |r| cos α = {float(length(r)):.2f} × {cosine:.2f}\n"
        "the length of the shadow of r on u",
        transform=ax.transAxes,
        ha="center",
        fontsize=SMALLEST_FONT + 1,
    )
    ax.set_aspect("equal")
    ax.set_xlim(-0.4, 3.2)
    ax.set_ylim(-1.15, 1.9)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title("the dot product as a projection", fontsize=11)
    return ax.figure


SIDE_STYLE = {
    1: ("tab:blue", "in front: p·n > a·n"),
    0: ("black", "on: p·n = a·n"),
    -1: ("tab:red", "behind: p·n < a·n"),
}


def plane_sides(axes: list[Axes] | None = None) -> Figure:
    """Two panels: points coloured by :func:`raykit.planes.plane_side` about a plane (a line in
    this 2D cross-section), and a triangle a, p, q with its normal (p - a) × (q - a) in 3D, not
    unit length. ``axes``: two, the second a 3D axes."""
    if axes is None:
        figure = plt.figure(figsize=(10, 4.8), layout="constrained")
        axes = [figure.add_subplot(1, 2, 1), figure.add_subplot(1, 2, 2, projection="3d")]
    ax, ax3 = axes
    a, n = np.array([0.0, 0.0]), np.array([0.75, 1.0])  # any length: the sides are its sign
    along = np.array([n[1], -n[0]]) / length(n)
    rng = np.random.default_rng(433)
    points = rng.uniform(-2, 2, (40, 2))
    points = np.vstack([points, [[-1.5, 1.125], [1.75, -1.3125]]])  # two on it: p·n = a·n exactly
    side = plane_side(points, a, n)
    ax.plot(*np.stack([a - 2.6 * along, a + 2.6 * along]).T, color="black", lw=2)
    ax.plot(*a, "ks")
    ax.annotate(
        "a",
        a,
        xytext=(-8, -8),
        textcoords="offset points",
        ha="right",
        va="top",
        fontsize=12,
        bbox={"boxstyle": "round,pad=0.1", "facecolor": "white", "edgecolor": "none"},
    )
    _arrow(ax, a, a + n, "n")
    for value, (color, label) in SIDE_STYLE.items():
        chosen = points[side == value]
        ax.plot(
            *chosen.T, "o", color=color, ms=5 + 3 * (value == 0), label=f"{label} ({len(chosen)})"
        )
    # the legend under the panel, where it hides no point
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.01), fontsize=SMALLEST_FONT, ncol=2)
    ax.set_xlim(-2.2, 2.2)
    ax.set_ylim(-2.2, 2.2)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title("front and back: plane_side(p, a, n)", fontsize=11)

    a3, p3, q3 = np.array([0.0, 0.0, 0.0]), np.array([2.0, 0.0, 0.0]), np.array([0.5, 1.5, 0.0])
    n3 = normal_from_points(a3, p3, q3)
    triangle = np.stack([a3, p3, q3, a3])
    ax3.plot(*triangle.T, color="0.3")
    ax3.plot_trisurf(*triangle[:3].T, color="0.85", alpha=0.6)
    centre = triangle[:3].mean(axis=0)
    ax3.quiver(*centre, *n3, color="tab:red", arrow_length_ratio=0.08, lw=1.6)
    ax3.quiver(*centre, *(n3 / length(n3)), color="tab:blue", arrow_length_ratio=0.2, lw=2)
    for point, name in ((a3, "a"), (p3, "p"), (q3, "q")):
        ax3.scatter(*point, color="black", s=12)
        # away from the triangle's middle, where its edges and the normals are
        clear_label(ax3, point, name, toward=225 if name == "a" else -45, fontsize=12)
    clear_label(
        ax3,
        centre + 0.8 * n3,
        f"n = (p - a) × (q - a)\n|n| = {length(n3):g}",
        toward=180,  # the side of the normal away from the box's back edges
        color="tab:red",
        fontsize=SMALLEST_FONT + 1,
    )
    clear_label(
        ax3,
        centre + n3 / length(n3),
        "unit n",
        toward=0,
        color="tab:blue",
        fontsize=SMALLEST_FONT + 1,
    )
    ax3.set_xlim(-0.5, 2.5)
    ax3.set_ylim(-0.5, 2.0)
    ax3.set_zlim(0, 3.2)
    ax3.set_box_aspect((3.0, 2.5, 3.2))
    ax3.view_init(elev=18, azim=-65)
    ax3.grid(False)  # the labels are set inside the box, where gridlines would cross them
    for axis in (ax3.xaxis, ax3.yaxis, ax3.zaxis):
        axis.set_ticklabels([])
    ax3.set_title("normal from three points:\nnormal does not mean normalized", fontsize=11)
    return ax.figure

"""The line-scan world's objects: balls (circles) and billboards (segments), seen from both sides.

The math is the 3D renderer's, one dimension down (shapes and the t > 0 rule per
:mod:`raykit.rays`):

* A ball is the 2D sphere, so :func:`raykit.spheres.hit_sphere` finds its hits with k = 2.
* A billboard from ``start`` to ``end`` lies on the line through ``start`` whose normal is
  a = end - start turned a quarter, so :func:`raykit.planes.hit_plane` finds where a ray meets
  that line. The hit's parameter along the segment is s = q·a / (a·a), q = p - start, and the
  hit counts for 0 <= s <= 1 (ends included).

A billboard shows one colour, or one row of an image: texel column min(floor(s·W), W - 1) of
row ``row`` (image row 0 is the top), so texel 0 is at ``start``. A texel with alpha < 128 is
a hole, as in 3D.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from raykit.billboards import Texels, colors_and_opacity
from raykit.hits import ColorAt, solid
from raykit.planes import hit_plane, hit_points_on_plane
from raykit.rays import MISS, dot
from raykit.spheres import hit_sphere


@dataclass(frozen=True)
class Ball:
    """A circle: ``center (2,)``, ``radius > 0``, ``color (3,)``; it moves by ``velocity (2,)``
    scene units per scan in a sweep."""

    center: np.ndarray
    radius: float
    color: np.ndarray
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    name: str | None = None

    def moved(self, scans: float) -> Ball:
        """This ball after ``scans`` scans of its motion."""
        return replace(self, center=self.center + scans * self.velocity)


@dataclass(frozen=True)
class Billboard:
    """A segment ``start`` -> ``end`` ``(2,)`` with a ``color (3,)`` or a ``texture`` row."""

    start: np.ndarray
    end: np.ndarray
    color: np.ndarray | None = None
    texture: Texels | None = None
    row: int = 0
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    name: str | None = None

    def moved(self, scans: float) -> Billboard:
        """This billboard after ``scans`` scans of its motion."""
        shift = scans * self.velocity
        return replace(self, start=self.start + shift, end=self.end + shift)


def hit_ball(origins: np.ndarray, directions: np.ndarray, ball: Ball) -> np.ndarray:
    """Nearest t > 0 ``(N,)`` of rays ``(N, 2)`` on the circle, or ``MISS``."""
    return hit_sphere(origins, directions, np.asarray(ball.center, float), ball.radius)


def hit_segment(
    origins: np.ndarray, directions: np.ndarray, billboard: Billboard
) -> tuple[np.ndarray, np.ndarray]:
    """Where rays ``(N, 2)`` meet the segment: ``t (N,)`` (``MISS`` off it) and ``s (N,)``."""
    # BEGIN SOLUTION
    # hint: the segment's line is a 2D plane through start with normal (end - start) turned a
    #       quarter: use hit_plane, then s = q·a / (a·a)
    start = np.asarray(billboard.start, float)
    a = np.asarray(billboard.end, float) - start
    n = np.array([-a[1], a[0]])
    t = hit_plane(origins, directions, start, n)
    s = dot(hit_points_on_plane(origins, directions, t, start), a) / dot(a, a)
    with np.errstate(invalid="ignore"):
        on_segment = (s >= 0) & (s <= 1)
    return np.where(on_segment, t, MISS), s
    # END SOLUTION


def segment_color_at(billboard: Billboard, s: np.ndarray) -> ColorAt:
    """The billboard's colours and opacity at the hits s ``(N,)`` of N rays, as a
    :data:`raykit.hits.ColorAt`: asked about some of the rays, it looks up only their texels."""
    if billboard.texture is None:
        return solid(billboard.color)

    def color_at(rays: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        texels = billboard.texture.rgba[billboard.row]
        column = np.minimum(np.floor(s[rays] * len(texels)), len(texels) - 1).astype(np.intp)
        return colors_and_opacity(texels[column])

    return color_at

"""Billboards: flat parallelograms with a colour or an image on them, seen from both sides.

Geometry. With the corners of the scene file and the edges

    a = upper_right - upper_left,   b = lower_left - upper_left,

the billboard is the set of points upper_left + alpha·a + beta·b with alpha, beta in [0, 1]
(edges included). It lies in the plane through upper_left with normal n = a × b, so a ray meets
it where it meets that plane (:func:`raykit.planes.hit_plane`), if the hit point's (alpha, beta)
fall in the unit square.

(alpha, beta) of a point q = p - upper_left in the plane come from the dual vectors of a and b,

    alpha = q·(b × n) / |n|²,   beta = q·(n × a) / |n|²,

which is q written in the basis (a, b): (b × n)·a = |n|², (b × n)·b = 0, and likewise for beta.

Texture lookup (nearest texel). For an image W texels wide and H high, with image row 0 at the
top (:mod:`raykit.io.textures`), the texel at (alpha, beta) is

    column = min(floor(alpha·W), W - 1),   row = min(floor(beta·H), H - 1),

so the upper-left texel sits at the upper_left corner whichever side the billboard is seen from
(from behind, the image is seen mirrored). A texel with alpha-channel < 128 is a hole: the ray
does not hit the billboard there and goes on to whatever lies behind.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Protocol

import numpy as np

from raykit.hits import ColorAt, solid
from raykit.materials import PLAIN, Material
from raykit.planes import hit_plane, hit_points_on_plane
from raykit.rays import MISS, cross, dot, length, normalize

OPAQUE_FROM = 128  # a texel whose alpha is below this is a hole


class Texels(Protocol):
    """What a billboard needs of its image: ``rgba (H, W, 4)`` uint8, row 0 the top row
    (:class:`raykit.io.textures.Texture` reads one from a file when first asked)."""

    width: int
    height: int

    @property
    def rgba(self) -> np.ndarray: ...


def colors_and_opacity(rgba: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Texels ``(M, 4)`` uint8 as colours ``(M, 3)`` in [0, 1] and opacity ``(M,)`` bool."""
    return rgba[:, :3] / 255.0, rgba[:, 3] >= OPAQUE_FROM


@dataclass(frozen=True)
class Billboard:
    """A parallelogram from three corners ``(3,)``, with a flat ``color (3,)`` or a ``texture``."""

    upper_left: np.ndarray
    lower_left: np.ndarray
    upper_right: np.ndarray
    color: np.ndarray | None = None
    texture: Texels | None = None
    name: str | None = None
    material: Material = PLAIN

    @cached_property
    def a(self) -> np.ndarray:
        """Edge upper_left -> upper_right, ``(3,)``: the direction of alpha (image columns)."""
        return _floats(self.upper_right) - _floats(self.upper_left)

    @cached_property
    def b(self) -> np.ndarray:
        """Edge upper_left -> lower_left, ``(3,)``: the direction of beta (image rows)."""
        return _floats(self.lower_left) - _floats(self.upper_left)

    @cached_property
    def n(self) -> np.ndarray:
        """Normal a × b, ``(3,)`` (not unit length)."""
        return cross(self.a, self.b)

    @cached_property
    def dual_axes(self) -> tuple[np.ndarray, np.ndarray]:
        """The dual vectors ((b × n)/|n|², (n × a)/|n|²) that turn a point into (alpha, beta)."""
        n_squared = dot(self.n, self.n)
        return cross(self.b, self.n) / n_squared, cross(self.n, self.a) / n_squared


def _floats(point) -> np.ndarray:
    """The point as a float array, keeping float32 as float32 (see raykit.engine.precision)."""
    point = np.asarray(point)
    return point if point.dtype.kind == "f" else point.astype(float)


def is_degenerate(a: np.ndarray, b: np.ndarray) -> bool:
    """True when edges a and b ``(3,)`` span no parallelogram (zero or parallel)."""
    return bool(length(cross(a, b)) <= 1e-12 * length(a) * length(b))


def hit_billboard(
    origins: np.ndarray, directions: np.ndarray, billboard: Billboard
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where rays ``(N, 3)`` meet the billboard's parallelogram, ignoring its texture.

    Returns ``t (N,)`` (``MISS`` outside the parallelogram) and the hit's ``alpha (N,)``,
    ``beta (N,)`` (NaN where the plane is missed).
    """
    # BEGIN SOLUTION
    # hint: t from hit_plane with n = a × b through upper_left; alpha = q·(b × n)/|n|², beta = q·(n
    #       × a)/|n|²; inside when both are in [0, 1]
    corner = _floats(billboard.upper_left)
    t = hit_plane(origins, directions, corner, billboard.n)
    q = hit_points_on_plane(origins, directions, t, corner)
    alpha_axis, beta_axis = billboard.dual_axes
    alpha = dot(q, alpha_axis)
    beta = dot(q, beta_axis)
    with np.errstate(invalid="ignore"):
        inside = (alpha >= 0) & (alpha <= 1) & (beta >= 0) & (beta <= 1)
    return np.where(inside, t, MISS), alpha, beta
    # END SOLUTION


def billboard_normals(billboard: Billboard, directions: np.ndarray) -> np.ndarray:
    """Unit normals ``(N, 3)`` of the billboard's side that rays ``(N, 3)`` arrive at: n = a × b
    normalised, turned round where it points away from the ray's origin (n·d > 0). A billboard
    has two sides and each is lit from its own side."""
    n = normalize(billboard.n)
    facing = np.where(dot(directions, n) > 0, -1.0, 1.0)
    return facing[:, None] * n


def texel_indices(
    alpha: np.ndarray, beta: np.ndarray, width: int, height: int
) -> tuple[np.ndarray, np.ndarray]:
    """Nearest-texel (row, column) ``(N,)`` ints for (alpha, beta) in [0, 1]²."""
    # BEGIN SOLUTION
    # hint: column = min(floor(alpha·W), W - 1), row = min(floor(beta·H), H - 1), as integers
    column = np.minimum(np.floor(alpha * width), width - 1).astype(np.intp)
    row = np.minimum(np.floor(beta * height), height - 1).astype(np.intp)
    return row, column
    # END SOLUTION


def billboard_color_at(billboard: Billboard, alpha: np.ndarray, beta: np.ndarray) -> ColorAt:
    """The billboard's colours and opacity at the hits (alpha, beta) ``(N,)`` of N rays, as a
    :data:`raykit.hits.ColorAt`: asked about some of the rays, it looks up only their texels."""
    if billboard.texture is None:
        return solid(billboard.color)

    def color_at(rays: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        texels = billboard.texture.rgba
        row, column = texel_indices(alpha[rays], beta[rays], texels.shape[1], texels.shape[0])
        return colors_and_opacity(texels[row, column])

    return color_at

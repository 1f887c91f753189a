"""Repeats :mod:`raykit.billboards` (and :mod:`raykit.planes`) for one ray: where it meets
a billboard, and the colour and opacity of the texel there."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from raykit.billboards import OPAQUE_FROM
from raykit.engine.compiled.compiling import ONE_RAY


@njit(**ONE_RAY)
def hit_billboard(o0, o1, o2, d0, d1, d2, arrays, board):
    """Repeats :func:`raykit.billboards.hit_billboard` (and :func:`raykit.planes.hit_plane`,
    :func:`raykit.planes.hit_points_on_plane`) for one ray and billboard ``board`` (counted
    among the billboards): ``(t, alpha, beta)``, t = inf off the parallelogram."""
    # scalars, not rows: a row of an array is a view whose reference count costs more than
    # the arithmetic
    a = (arrays.corners[board, 0], arrays.corners[board, 1], arrays.corners[board, 2])
    n = (arrays.n[board, 0], arrays.n[board, 1], arrays.n[board, 2])
    alpha_axis = (
        arrays.alpha_axes[board, 0],
        arrays.alpha_axes[board, 1],
        arrays.alpha_axes[board, 2],
    )
    beta_axis = (arrays.beta_axes[board, 0], arrays.beta_axes[board, 1], arrays.beta_axes[board, 2])
    d_dot_n = d0 * n[0] + d1 * n[1] + d2 * n[2]
    a_minus_o_dot_n = (a[0] - o0) * n[0] + (a[1] - o1) * n[1] + (a[2] - o2) * n[2]
    if d_dot_n == 0:
        return np.inf, np.nan, np.nan
    t = a_minus_o_dot_n / d_dot_n
    if not (t > 0 and t < np.inf):  # a miss, or t = inf, whose point is NaN
        return np.inf, np.nan, np.nan
    q0 = (o0 - a[0]) + t * d0
    q1 = (o1 - a[1]) + t * d1
    q2 = (o2 - a[2]) + t * d2
    alpha = q0 * alpha_axis[0] + q1 * alpha_axis[1] + q2 * alpha_axis[2]
    beta = q0 * beta_axis[0] + q1 * beta_axis[1] + q2 * beta_axis[2]
    if alpha >= 0 and alpha <= 1 and beta >= 0 and beta <= 1:
        return t, alpha, beta
    return np.inf, alpha, beta


@njit(**ONE_RAY)
def billboard_color_at(arrays, board, alpha, beta):
    """Repeats :func:`raykit.billboards.billboard_color_at` (with
    :func:`~raykit.billboards.texel_indices` and :func:`~raykit.billboards.colors_and_opacity`)
    for one hit: ``(r, g, b, opaque)``, the texel's colour and opacity."""
    start = arrays.texture_start[board]
    if start < 0:
        colors = arrays.board_colors
        return colors[board, 0], colors[board, 1], colors[board, 2], True
    width = arrays.texture_width[board]
    height = arrays.texture_height[board]
    column = min(math.floor(alpha * width), width - 1)
    row = min(math.floor(beta * height), height - 1)
    texel = start + int(row) * width + int(column)
    # each channel over 255.0 in float64 as colors_and_opacity divides it, at the lookup: the
    # texels stay bytes, so a texture is never converted whole
    texels = arrays.texels
    return (texels[texel, 0] / 255.0, texels[texel, 1] / 255.0, texels[texel, 2] / 255.0,
            texels[texel, 3] >= OPAQUE_FROM)  # fmt: skip

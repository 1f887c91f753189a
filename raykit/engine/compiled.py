"""The compiled engine: the renderer's loop as machine code (numba), one ray at a time.

Install with ``pip install "raykit[fast]"``; :func:`raykit.render.render` takes it with
``engine="compiled"``, or by itself for large renders (``engine="auto"``,
:mod:`raykit.engine.choice`). Without numba nothing imports this module.

What it repeats, and how it is held to it. The lecture's numpy functions are the reference.
Each kernel below names the function it repeats and does *the same float64 operations in the
same order* on one ray, so its answers agree with the reference bit for bit
(``tests/test_compiled.py`` checks t values, object indices and colours on 10^5 seeded random
rays per kernel, the stability cases, and the PNG bytes of every example scene). Dot products
are summed left to right with no fused multiply-add, as :func:`raykit.rays.dot` sums them
(numba, like numpy, contracts a·b + c into an FMA only under fastmath, which is off).

What it skips. Primary rays: the image is cut into TILE x TILE tiles, and each tile keeps the
objects whose screen rectangle (:mod:`raykit.engine.screen_bounds`) meets it, nearest first; a
viewing ray tests only those whose rectangle holds its image point, and stops at the first
object that cannot come nearer than the hit it has (:func:`screen_tiles`). Shadow and mirror
rays: they walk a bounding volume hierarchy (the tree of :mod:`raykit.engine.bvh`, built by
the same code), nearer child first, leaving every box that starts beyond the nearest hit found.
Either way a tie keeps the lower object index, whatever order objects come in, and a cut-out
texel is no hit: the answer is :func:`raykit.render.cast`'s.

Lit scenes. Lights, shadows and mirrors are shaded by the reference itself
(:func:`raykit.shading.shade`), this engine finding the nearest hits of the primary rays and of
every shadow and mirror ray (:func:`caster`).

Compiling. The kernels compile on first use, which says so on standard error, and are cached
on disk in a folder named after a hash of this file's source
(:func:`raykit.engine.choice.cache_folder`): editing a kernel makes a new folder, so the cache
never serves kernels compiled from older source (numba's own check, the file's time and size,
would miss an edit that keeps both). Only float64 is compiled.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from functools import partial
from typing import NamedTuple

import numpy as np

from raykit.camera import centre_sample, region_points, sample_offsets
from raykit.engine.adaptive import edge_pixels, refine
from raykit.engine.arrays import SceneArrays
from raykit.engine.bvh import BVH
from raykit.engine.choice import cache_folder
from raykit.engine.screen_bounds import object_bounds
from raykit.engine.tiles import regions
from raykit.hits import Hits
from raykit.scene import Scene
from raykit.shading import needs_shading, shade

COMPILE_SECONDS = 20  # how long the first compile took on the 2-core machine (measured: 10-18 s)
STACK = 128  # nodes a ray may have still to visit: a median-split tree of 2^63 objects is 63 deep
TILE = 16  # pixels a side of the tiles that primary rays take their objects from
ROWS_PER_CALL = 32  # rows of pixels per kernel call: a progress bar moves, memory stays small


_CACHE = cache_folder()  # keyed on this file's source
_FIRST_USE = _CACHE is None or not (_CACHE / "compiled.ok").exists()
if _FIRST_USE:
    print(f"compiling raykit's fast kernels, once: ~{COMPILE_SECONDS} s", file=sys.stderr)

import numba  # noqa: E402  (after the message: importing numba takes a while too)
from numba import njit, prange  # noqa: E402

numba.config.CACHE_DIR = str(_CACHE) if _CACHE is not None else ""  # read as kernels are made
_jit = dict(cache=_CACHE is not None, error_model="numpy", nogil=True)
# one ray's kernels are inlined into the loops: a call would pass the scene's arrays by value,
# with a reference count per array, which cost more than the ray's arithmetic (measured)
_one_ray = dict(_jit, inline="always")


class Tree(NamedTuple):
    """A BVH (:class:`raykit.engine.bvh.BVH`, :func:`scene_tree`) as the kernels walk it."""

    lower: np.ndarray
    upper: np.ndarray
    children: np.ndarray
    first: np.ndarray
    count: np.ndarray
    order: np.ndarray


class Arrays(NamedTuple):
    """A scene as flat arrays for the kernels, in object index order (:mod:`raykit.scene`):
    spheres ``centers (S, 3)``, ``radii (S,)``, ``sphere_colors (S, 3)``
    (:class:`raykit.engine.arrays.SceneArrays`); billboards' ``corners (B, 3)`` (upper_left),
    normals ``n (B, 3)`` (a × b), ``alpha_axes``, ``beta_axes (B, 3)``
    (:attr:`raykit.billboards.Billboard.dual_axes`), flat ``board_colors (B, 3)``, and textures:
    ``texture_start (B,)`` (-1: none) into the texels of all textures ``texels (T, 4)`` uint8,
    row by row, ``texture_width``, ``texture_height (B,)``; the ``background (3,)``."""

    centers: np.ndarray
    radii: np.ndarray
    sphere_colors: np.ndarray
    corners: np.ndarray
    n: np.ndarray
    alpha_axes: np.ndarray
    beta_axes: np.ndarray
    board_colors: np.ndarray
    texture_start: np.ndarray
    texture_width: np.ndarray
    texture_height: np.ndarray
    texels: np.ndarray
    background: np.ndarray


def scene_arrays(scene: Scene) -> Arrays:
    """The scene's :class:`Arrays`, each number computed by the reference's own code (the
    spheres' :class:`~raykit.engine.arrays.SceneArrays`, the billboards' cached edges and dual
    axes), so the kernels start from the same bits. A texture is decoded here only if it is on
    a billboard."""
    spheres = SceneArrays.of(scene)
    boards = scene.billboards
    f3 = lambda rows: np.array(rows, dtype=float).reshape(-1, 3)  # noqa: E731
    starts, widths, heights, texels, used = [], [], [], [], 0
    for board in boards:
        if board.texture is None:
            starts.append(-1), widths.append(0), heights.append(0)
            continue
        rgba = board.texture.rgba
        starts.append(used), widths.append(rgba.shape[1]), heights.append(rgba.shape[0])
        texels.append(rgba.reshape(-1, 4))
        used += rgba.shape[0] * rgba.shape[1]
    return Arrays(
        spheres.centers.astype(float).reshape(-1, 3),
        spheres.radii.astype(float),
        spheres.sphere_colors,
        f3([np.asarray(b.upper_left, float) for b in boards]),
        f3([b.n for b in boards]),
        f3([b.dual_axes[0] for b in boards]),
        f3([b.dual_axes[1] for b in boards]),
        f3([b.color if b.color is not None else np.zeros(3) for b in boards]),
        np.array(starts, dtype=np.int64),
        np.array(widths, dtype=np.int64),
        np.array(heights, dtype=np.int64),
        np.concatenate(texels) if texels else np.zeros((0, 4), np.uint8),
        np.asarray(scene.background, dtype=float),
    )


def scene_tree(scene: Scene) -> Tree:
    """The scene's BVH, built by the numpy engine's own builder, as a :class:`Tree`."""
    bvh = BVH.build(scene)
    return Tree(
        bvh.lower.astype(float).reshape(-1, 3),
        bvh.upper.astype(float).reshape(-1, 3),
        bvh.children.astype(np.int64).reshape(-1, 2),
        *(part.astype(np.int64) for part in (bvh.first, bvh.count, bvh.order)),
    )


# ---- the kernels: one ray each ---------------------------------------------------------------


@njit(**_one_ray)
def nearest_positive(t0: float, t1: float) -> float:
    """Repeats :func:`raykit.rays.nearest_positive` for one ray (np.fmin/np.fmax ignore a NaN
    partner, as here)."""
    if math.isnan(t0):
        t_near = t1
        t_far = t1
    elif math.isnan(t1):
        t_near = t0
        t_far = t0
    else:
        t_near = min(t0, t1)
        t_far = max(t0, t1)
    if t_near > 0:
        return t_near
    if t_far > 0:
        return t_far
    return np.inf


@njit(**_one_ray)
def hit_sphere(o0, o1, o2, d0, d1, d2, c0, c1, c2, R) -> float:
    """Repeats :func:`raykit.spheres.hit_sphere` (through :func:`raykit.spheres.sphere_roots`,
    the stable form; its docstring derives it from the slide's A, B, C and D) for one ray."""
    f0 = o0 - c0
    f1 = o1 - c1
    f2 = o2 - c2
    A = d0 * d0 + d1 * d1 + d2 * d2
    b = f0 * d0 + f1 * d1 + f2 * d2  # b' = B/2
    C = (f0 * f0 + f1 * f1 + f2 * f2) - R * R
    k = b / A
    x0 = f0 - k * d0  # centre -> closest point on the line
    x1 = f1 - k * d1
    x2 = f2 - k * d2
    discriminant = A * (R * R - (x0 * x0 + x1 * x1 + x2 * x2))  # Δ = D/4
    if not discriminant >= 0:
        return np.inf
    q = -(b + math.copysign(math.sqrt(discriminant), b))
    return nearest_positive(q / A, C / q)


@njit(**_one_ray)
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


@njit(**_one_ray)
def billboard_color(arrays, board, alpha, beta):
    """Repeats :func:`raykit.billboards.billboard_color_at` (with
    :func:`~raykit.billboards.texel_indices` and :func:`~raykit.billboards.colors_and_opacity`)
    for one hit: ``(r, g, b, opaque)``."""
    start = arrays.texture_start[board]
    if start < 0:
        colors = arrays.board_colors
        return colors[board, 0], colors[board, 1], colors[board, 2], True
    width = arrays.texture_width[board]
    height = arrays.texture_height[board]
    column = min(math.floor(alpha * width), width - 1)
    row = min(math.floor(beta * height), height - 1)
    texel = start + int(row) * width + int(column)
    texels = arrays.texels
    return (
        texels[texel, 0] / 255.0,
        texels[texel, 1] / 255.0,
        texels[texel, 2] / 255.0,
        texels[texel, 3] >= 128,
    )


@njit(**_one_ray)
def enters(o0, o1, o2, i0, i1, i2, lower, upper, node, t_max):
    """Repeats the slab test of :mod:`raykit.engine.bvh` (``_enters``) for one ray with inverse
    direction (i0, i1, i2): ``(entered, near)``, whether it enters the box by t_max, and where."""
    near = -np.inf
    far = np.inf
    for axis, o, i in ((0, o0, i0), (1, o1, i1), (2, o2, i2)):
        t1 = (lower[node, axis] - o) * i
        t2 = (upper[node, axis] - o) * i
        if math.isnan(t1) or math.isnan(t2):
            continue  # a ray parallel to a slab, starting on its face: the slab is open
        near = max(near, min(t1, t2))
        far = min(far, max(t1, t2))
    return far >= near and far >= 0 and near <= t_max, near


@njit(**_one_ray)
def offer(arrays, obj, o0, o1, o2, d0, d1, d2, best, best_t, r, g, b):
    """Repeats :meth:`raykit.hits.Hits.keep_nearer` for one ray and object ``obj``: the nearest
    hit so far ``(best, best_t, r, g, b)``, replaced by the object's where it is nearer and
    opaque there, or as near and of a lower index (objects may come in any order here; the
    reference offers them in index order, so a tie keeps the lower index)."""
    spheres = len(arrays.radii)
    if obj < spheres:
        centers = arrays.centers
        t = hit_sphere(
            o0, o1, o2, d0, d1, d2, centers[obj, 0], centers[obj, 1], centers[obj, 2],
            arrays.radii[obj],
        )  # fmt: skip
        if t < best_t or (t == best_t and t < np.inf and obj < best):
            colors = arrays.sphere_colors
            return obj, t, colors[obj, 0], colors[obj, 1], colors[obj, 2]
        return best, best_t, r, g, b
    board = obj - spheres
    t, alpha, beta = hit_billboard(o0, o1, o2, d0, d1, d2, arrays, board)
    if t < best_t or (t == best_t and t < np.inf and obj < best):
        cr, cg, cb, opaque = billboard_color(arrays, board, alpha, beta)
        if opaque:
            return obj, t, cr, cg, cb
    return best, best_t, r, g, b


@njit(**_one_ray)
def nearest_hit(arrays, tree, stack, o0, o1, o2, d0, d1, d2, t_max):
    """Repeats :func:`raykit.render.cast` for one ray, through the BVH: ``(index, t, r, g, b)``,
    the nearest opaque hit with t > 0 (the lower index on a tie), or (-1, inf, background).
    Hits at t > t_max may be left out (shadow rays). ``stack``: room for the nodes still to
    visit, (STACK,) ints, reused from ray to ray."""
    background = arrays.background
    best, best_t = -1, np.inf
    r, g, b = background[0], background[1], background[2]
    if len(tree.order) == 0:
        return best, best_t, r, g, b
    i0, i1, i2 = 1.0 / d0, 1.0 / d1, 1.0 / d2  # ±inf along an axis the ray does not move
    lower, upper = tree.lower, tree.upper
    stack[0] = 0
    top = 1
    while top > 0:
        top -= 1
        node = stack[top]
        reach = min(best_t, t_max)  # a box that starts beyond the nearest hit holds no nearer one
        entered, _ = enters(o0, o1, o2, i0, i1, i2, lower, upper, node, reach)
        if not entered:
            continue
        left = tree.children[node, 0]
        if left >= 0:
            right = tree.children[node, 1]
            _, near_left = enters(o0, o1, o2, i0, i1, i2, lower, upper, left, reach)
            _, near_right = enters(o0, o1, o2, i0, i1, i2, lower, upper, right, reach)
            if near_left <= near_right:  # the nearer child is searched first: pushed last
                stack[top] = right
                stack[top + 1] = left
            else:
                stack[top] = left
                stack[top + 1] = right
            top += 2
            continue
        for k in range(tree.first[node], tree.first[node] + tree.count[node]):
            best, best_t, r, g, b = offer(
                arrays, tree.order[k], o0, o1, o2, d0, d1, d2, best, best_t, r, g, b
            )
    return best, best_t, r, g, b


@njit(**_one_ray)
def viewing_ray(camera, x, y):
    """Repeats :func:`raykit.camera.rays_through` for one image point (x, y): ``(o0, o1, o2,
    d0, d1, d2)``. ``camera`` is (eye (3,), u, v, w, (-Wp/2, Wp/width, Hp/2, Hp/height, d,
    orthographic))."""
    eye, u, v, w, plane = camera
    s = plane[0] + x * plane[1]
    t = plane[2] - y * plane[3]
    p0 = s * u[0] + t * v[0]
    p1 = s * u[1] + t * v[1]
    p2 = s * u[2] + t * v[2]
    if plane[5] != 0:  # orthographic: origin eye + s·u + t·v, direction -w
        return eye[0] + p0, eye[1] + p1, eye[2] + p2, -w[0], -w[1], -w[2]
    d = plane[4]
    x0 = p0 - d * w[0]
    x1 = p1 - d * w[1]
    x2 = p2 - d * w[2]
    length = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    return eye[0], eye[1], eye[2], x0 / length, x1 / length, x2 / length


@njit(**_jit)
def bin_by_tile(bounds, by_distance, tiles_x, tiles_y):
    """Each tile's objects, for primary rays: the objects ``by_distance (K,)`` (nearest first)
    whose screen rectangle ``bounds (K, 4)`` (x0, x1, y0, y1; NaN: never seen,
    :func:`raykit.engine.screen_bounds.object_bounds`) meets the tile of TILE x TILE pixels.
    Returns ``start (tiles + 1,)`` and ``objects``: tile k's are objects[start[k]:start[k+1]],
    nearest first."""
    count = np.zeros(tiles_x * tiles_y + 1, dtype=np.int64)
    for fill in (False, True):  # count, then fill
        if fill:
            start = np.cumsum(count)
            cursor = start[:-1].copy()
            objects = np.empty(start[-1], dtype=np.int64)
        else:
            start = count
            cursor = count[:0]
            objects = np.empty(0, dtype=np.int64)
        for obj in by_distance:
            x0, x1, y0, y1 = bounds[obj, 0], bounds[obj, 1], bounds[obj, 2], bounds[obj, 3]
            if not (x0 <= x1 and y0 <= y1):
                continue
            left, right = max(0, int(x0 // TILE)), min(tiles_x - 1, int(x1 // TILE))
            top, bottom = max(0, int(y0 // TILE)), min(tiles_y - 1, int(y1 // TILE))
            for ty in range(top, bottom + 1):
                for tx in range(left, right + 1):
                    tile = ty * tiles_x + tx
                    if fill:
                        objects[cursor[tile]] = obj
                        cursor[tile] += 1
                    else:
                        count[tile + 1] += 1
    return start, objects


@njit(**_one_ray)
def nearest_in_tile(arrays, tiles, x, y, o0, o1, o2, d0, d1, d2):
    """:func:`nearest_hit` for the viewing ray through image point (x, y): only the objects of
    its tile whose screen rectangle holds the point (as :meth:`raykit.engine.tiles.Region.holding`
    decides), nearest first, until the next can only be farther than the hit found."""
    start, objects, bounds, closest, tiles_x = tiles
    background = arrays.background
    best, best_t = -1, np.inf
    r, g, b = background[0], background[1], background[2]
    tile = (int(y) // TILE) * tiles_x + int(x) // TILE
    for k in range(start[tile], start[tile + 1]):
        obj = objects[k]
        if closest[obj] > best_t:
            break  # every object from here on is farther than the hit
        if (
            bounds[obj, 0] <= x
            and x <= bounds[obj, 1]
            and bounds[obj, 2] <= y
            and y <= bounds[obj, 3]
        ):
            best, best_t, r, g, b = offer(
                arrays, obj, o0, o1, o2, d0, d1, d2, best, best_t, r, g, b
            )
    return best, best_t, r, g, b


# ---- the loops: many rays, both cores --------------------------------------------------------


@njit(parallel=True, **_jit)
def cast_rays(arrays, tree, origins, directions, t_max):
    """:func:`nearest_hit` for each ray ``(N, 3)``: ``index (N,)``, ``t (N,)``, ``color (N, 3)``."""
    count = len(origins)
    index = np.empty(count, dtype=np.int64)
    t = np.empty(count)
    color = np.empty((count, 3))
    for chunk in prange((count + 255) // 256):
        stack = np.empty(STACK, dtype=np.int64)
        for i in range(chunk * 256, min(count, chunk * 256 + 256)):
            o, d = origins[i], directions[i]
            index[i], t[i], color[i, 0], color[i, 1], color[i, 2] = nearest_hit(
                arrays, tree, stack, o[0], o[1], o[2], d[0], d[1], d[2], t_max[i]
            )
    return index, t, color


@njit(parallel=True, **_jit)
def trace_rows(arrays, tiles, camera, rows, width, offsets, centre):
    """The flat-colour render of whole image rows ``rows (R,)``: per pixel, the sum of its
    samples' colours at ``offsets (S, 2)`` in order (as :class:`raykit.engine.regions.Image`
    sums them), and the object index and t of the ray through the pixel centre, which is
    sample ``centre`` (-1: cast one more ray there). Returns ``rgb (R, W, 3)``, ``index``,
    ``t (R, W)``."""
    rgb = np.zeros((len(rows), width, 3))
    index = np.empty((len(rows), width), dtype=np.int64)
    t = np.empty((len(rows), width))
    for i in prange(len(rows)):
        row = rows[i]
        for col in range(width):
            for sample in range(len(offsets)):
                x, y = col + offsets[sample, 0], row + offsets[sample, 1]
                o0, o1, o2, d0, d1, d2 = viewing_ray(camera, x, y)
                hit, t_hit, r, g, b = nearest_in_tile(arrays, tiles, x, y, o0, o1, o2, d0, d1, d2)
                rgb[i, col, 0] += r
                rgb[i, col, 1] += g
                rgb[i, col, 2] += b
                if sample == centre:
                    index[i, col], t[i, col] = hit, t_hit
            if centre < 0:
                x, y = col + 0.5, row + 0.5
                o0, o1, o2, d0, d1, d2 = viewing_ray(camera, x, y)
                hit, t_hit, r, g, b = nearest_in_tile(arrays, tiles, x, y, o0, o1, o2, d0, d1, d2)
                index[i, col], t[i, col] = hit, t_hit
    return rgb, index, t


@njit(parallel=True, **_jit)
def trace_points(arrays, tiles, camera, x, y):
    """Origins, directions ``(N, 3)`` and nearest hits of the rays through image points (x, y)
    ``(N,)``: the viewing rays of :func:`raykit.camera.rays_through`, cast."""
    count = len(x)
    origins = np.empty((count, 3))
    directions = np.empty((count, 3))
    index = np.empty(count, dtype=np.int64)
    t = np.empty(count)
    color = np.empty((count, 3))
    for chunk in prange((count + 255) // 256):
        for i in range(chunk * 256, min(count, chunk * 256 + 256)):
            o0, o1, o2, d0, d1, d2 = viewing_ray(camera, x[i], y[i])
            origins[i, 0], origins[i, 1], origins[i, 2] = o0, o1, o2
            directions[i, 0], directions[i, 1], directions[i, 2] = d0, d1, d2
            index[i], t[i], color[i, 0], color[i, 1], color[i, 2] = nearest_in_tile(
                arrays, tiles, x[i], y[i], o0, o1, o2, d0, d1, d2
            )
    return origins, directions, index, t, color


# ---- the renderer ----------------------------------------------------------------------------


def camera_tuple(scene: Scene) -> tuple:
    """The camera's numbers as :func:`rays_through` computes them (see :func:`viewing_ray`)."""
    camera = scene.camera
    u, v, w = camera.frame
    Wp, Hp = camera.plane_size
    plane = np.array(
        [-Wp / 2, Wp / camera.width, Hp / 2, Hp / camera.height, camera.d,
         float(camera.projection == "orthographic")]
    )  # fmt: skip
    eye = np.asarray(camera.eye, dtype=float)
    return eye, *(np.asarray(x, dtype=float) for x in (u, v, w)), plane


def screen_tiles(scene: Scene, arrays: Arrays) -> tuple:
    """The primary rays' skip: every object's screen rectangle
    (:func:`raykit.engine.screen_bounds.object_bounds`, conservative), a lower bound on the t
    at which a viewing ray can meet it (``closest (K,)``: a sphere's distance from the eye less
    its radius, or in front of the image plane for orthographic rays, less a rounding margin; 0
    for a billboard), and each TILE x TILE tile's objects nearest first
    (:func:`bin_by_tile`): ``(start, objects, bounds, closest, tiles_x)``."""
    camera = scene.camera
    bounds = object_bounds(camera, scene.objects).reshape(-1, 4)
    closest = np.zeros(len(scene.objects))
    if scene.spheres:
        centers, radii = arrays.centers, arrays.radii
        eye = np.asarray(camera.eye, dtype=float)
        if camera.projection == "orthographic":
            distance = (centers - eye) @ -camera.frame[2]
        else:
            distance = np.linalg.norm(centers - eye, axis=1)
        margin = 1e-9 * (np.abs(distance) + radii + np.abs(eye).max() + np.abs(centers).max(axis=1))
        closest[: len(radii)] = np.maximum(0.0, distance - radii - margin)
    tiles_x = -(-camera.width // TILE)
    tiles_y = -(-camera.height // TILE)
    by_distance = np.argsort(closest, kind="stable")
    start, objects = bin_by_tile(bounds, by_distance, tiles_x, tiles_y)
    return start, objects, bounds, closest, tiles_x


def caster(scene: Scene, arrays: Arrays | None = None) -> Callable[..., Hits]:
    """A :data:`raykit.shadows.Caster` over the whole scene: the nearest hits of any rays, as
    :func:`raykit.render.secondary_caster` gives them, found by :func:`cast_rays`."""
    arrays = arrays or scene_arrays(scene)
    tree = scene_tree(scene)

    def cast(origins, directions, t_max=None) -> Hits:
        origins = np.ascontiguousarray(origins, dtype=float)
        directions = np.ascontiguousarray(directions, dtype=float)
        t_max = np.full(len(origins), np.inf) if t_max is None else np.asarray(t_max, float)
        return Hits(*cast_rays(arrays, tree, origins, directions, t_max))

    return cast


def render(scene: Scene, samples: int = 1, *, adaptive: bool = False, progress=None):
    """What :func:`raykit.render.render` renders, the same bits, with the kernels above:
    ``(rgb (H, W, 3), object_index (H, W), t (H, W))``. ``progress`` is told each band of
    finished pixels, as the numpy engine tells it each tile."""
    started = time.perf_counter()
    sample_offsets(samples)  # refuses n < 1 before any work
    n = 1 if adaptive else samples  # adaptive: one ray per pixel first, as the numpy engine
    lit = needs_shading(scene)
    arrays = scene_arrays(scene)
    tiles = screen_tiles(scene, arrays)
    camera = camera_tuple(scene)
    if lit:
        colors = partial(_shaded, scene, arrays, tiles, camera, caster(scene, arrays))
        rgb, index, t = _render_lit(scene, colors, n, progress)
    else:
        colors = partial(_flat, arrays, tiles, camera)
        rgb, index, t = _render_flat(scene, arrays, tiles, camera, n, progress)
    if adaptive and samples > 1:  # the numpy engine's refinement, with these colours
        edge = edge_pixels(rgb, index)
        refine(
            regions(scene, skip_hidden=False), lambda _, x, y: colors(x, y)[0], rgb, edge, samples
        )
    _compiled_once(started)
    return rgb, index, t


def _flat(arrays, tiles, camera, x, y):
    """The flat colours ``(N, 3)``, object indices and t ``(N,)`` of the viewing rays through
    image points (x, y) ``(N,)``."""
    _, _, index, t, color = trace_points(arrays, tiles, camera, x, y)
    return color, index, t


def _shaded(scene, arrays, tiles, camera, cast, x, y):
    """As :func:`_flat`, the colours shaded by the reference (:func:`raykit.shading.shade`)."""
    origins, directions, index, t, color = trace_points(arrays, tiles, camera, x, y)
    return shade(scene, cast, origins, directions, Hits(index, t, color)), index, t


def _bands(height: int):
    for start in range(0, height, ROWS_PER_CALL):
        yield np.arange(start, min(start + ROWS_PER_CALL, height), dtype=np.int64)


def _render_flat(scene, arrays, tiles, camera, samples, progress):
    """Whole rows at a time, the n x n samples of each pixel summed inside the kernel."""
    width, height = scene.camera.width, scene.camera.height
    offsets = sample_offsets(samples)
    centre = centre_sample(samples)
    rgb = np.empty((height, width, 3))
    index = np.empty((height, width), dtype=np.int64)
    t = np.empty((height, width))
    for rows in _bands(height):
        band = trace_rows(
            arrays, tiles, camera, rows, width, offsets, -1 if centre is None else centre
        )
        rgb[rows], index[rows], t[rows] = band[0] / len(offsets), band[1], band[2]
        if progress is not None:
            progress(len(rows) * width)
    return rgb, index, t


def _render_lit(scene, colors, samples, progress):
    """Band by band and offset by offset, as the numpy engine's batches go, each sample
    offset's ``colors(x, y)`` added in order."""
    width, height = scene.camera.width, scene.camera.height
    offsets = sample_offsets(samples)
    centre = centre_sample(samples)
    rgb = np.zeros((height, width, 3))
    index = np.empty((height, width), dtype=np.int64)
    t = np.empty((height, width))
    for rows in _bands(height):
        for k, (a, b) in enumerate([*offsets, (0.5, 0.5)] if centre is None else offsets):
            x, y = region_points(rows, range(width), a, b)
            color, hit, t_hit = colors(x, y)
            if k < len(offsets):  # else the centre ray of an even n, cast for its hits only
                rgb[rows] += color.reshape(len(rows), width, 3)
            if k == (len(offsets) if centre is None else centre):
                index[rows], t[rows] = hit.reshape(-1, width), t_hit.reshape(-1, width)
        if progress is not None:
            progress(len(rows) * width)
    return rgb / len(offsets), index, t


def _compiled_once(started: float) -> None:
    """After the first render of a fresh cache: mark it, and say how long compiling took."""
    global _FIRST_USE
    if _FIRST_USE and _CACHE is not None:
        (_CACHE / "compiled.ok").write_text(f"{time.perf_counter() - started:.1f} s\n")
    _FIRST_USE = False


__all__ = ["render", "caster", "cast_rays", "scene_arrays", "screen_tiles"]

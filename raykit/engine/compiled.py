"""The compiled engine: the renderer's loop as machine code (numba), ray by ray or in packets.

Install with ``pip install "raykit[fast]"``; :func:`raykit.render.render` takes it with
``engine="compiled"``, or by itself for large renders (``engine="auto"``,
:mod:`raykit.engine.choice`). Without numba nothing imports this module.

What it repeats, and how it is held to it. The lecture's numpy functions are the reference.
Each kernel below names the function it repeats and does *the same float64 operations in the
same order* on one ray, so its answers agree with the reference bit for bit, but for one pow
(below): ``tests/test_compiled.py`` checks t values, object indices and colours on 10^5
seeded random rays per kernel, the stability cases, and the PNG bytes of every example scene.
Dot products are summed left to right with no fused multiply-add, as :func:`raykit.rays.dot`
sums them (numba, like numpy, contracts a·b + c into an FMA only under fastmath, which is off).

What it skips. Primary rays: the image is cut into square tiles (:func:`tile_side`: 16 or 8
pixels a side, 4 in a crowded picture), and each tile keeps the objects whose screen rectangle
(:mod:`raykit.engine.screen_bounds`) meets it, nearest first (:func:`screen_tiles`). A tile no
object is seen in gets the background and no ray; elsewhere a viewing ray tests only the
objects whose rectangle holds its image point, and stops at the first that cannot come nearer
than the hit it has: one ray at a time in a crowded picture, else a whole tile's rays at once,
in vectors, with masks for what each ray would skip (:func:`primary_rays`). Shadow rays from
what a tile sees test only the objects that may lie between it and each light: the tile's
viewing rays are all traced first, then each light's volume of shadow rays from the box of
their surface points picks its candidates from the scene (:func:`shadow_lists`; with too many,
the rays walk the tree). Other shadow rays and mirror rays walk a bounding volume hierarchy
(the tree of :mod:`raykit.engine.bvh`, built by the same code), nearer child first, leaving
every box that starts beyond the nearest hit found, or in a scene of a few objects test each
(:data:`DIRECT_HITS`); a shadow ray stops at its first blocker.
Either way a tie keeps the lower object index, whatever order objects come in, and a cut-out
texel is no hit: the answer is :func:`raykit.render.cast`'s. All of it is made once per scene
by :func:`prepare`, which a caller may keep and render many times.

Lit scenes. :func:`shade_ray` and :func:`surface_color` repeat :mod:`raykit.shading` for one
ray: ambient, Lambert and Blinn-Phong per light, shadow rays (:mod:`raykit.shadows`, through the
BVH) and mirror bounces (:mod:`raykit.mirrors`), with the surface points and offsets of
:mod:`raykit.surfaces`. A job's viewing rays are shaded together, light by light, in lanes
(:func:`surface_lanes`, :func:`light_lanes`): each ray's operations in the same order, the
steps that every ray takes in vector instructions, and the shadow rays against the tile's
lists; a mirror's rays then go on one at a time (:func:`bounce_on`). One operation differs:
the highlight's power is the C library's pow here and numpy's vectorised power in the
reference, which disagree by one unit in the last place on a few per cent of points; with the
reference given the same pow, the two engines agree bit for bit, and as they stand, within 4
units in the last place and to the PNG byte (tests).

Compiling. The kernels compile on first use, which says so on standard error, and are cached
on disk in a folder named after a hash of this file's source and its folder
(:func:`raykit.engine.choice.cache_folder`): editing a kernel makes a new folder, so the cache
never serves kernels compiled from older source, whatever numba's own check of the source
(in older numba, the file's time and size, which an edit may keep). Only float64 is compiled.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from raykit.billboards import colors_and_opacity
from raykit.camera import centre_sample, sample_offsets
from raykit.engine.adaptive import edge_pixels, refine
from raykit.engine.arrays import SceneArrays
from raykit.engine.bvh import BVH
from raykit.engine.choice import cache_folder
from raykit.engine.screen_bounds import scene_bounds
from raykit.engine.tiles import regions
from raykit.hits import Hits
from raykit.lights import PointLight, toward_light
from raykit.rays import dot, length, normalize
from raykit.scene import Scene
from raykit.shading import casts_shadows, needs_shading
from raykit.surfaces import OFFSET_FACTOR

# about the first compile, as benchmarks/engines.py times it (docs/benchmarks/engines.md, 2)
COMPILE_SECONDS = 240
EPS = float(np.finfo(np.float64).eps)  # the rounding unit of raykit.surfaces' error bound
STACK = 128  # nodes a ray may have still to visit: a median-split tree of 2^63 objects is 63 deep
ROWS_PER_CALL = 32  # rows of pixels per kernel call when a progress bar is to move


_CACHE = cache_folder()  # keyed on this file's source and where it is
_FIRST_USE = _CACHE is None or not (_CACHE / "compiled.ok").exists()
if _FIRST_USE:
    print(f"compiling raykit's fast kernels, once: ~{COMPILE_SECONDS} s", file=sys.stderr)

import numba  # noqa: E402  (after the message: importing numba takes a while too)
from numba import njit, prange  # noqa: E402
from numba.core import types  # noqa: E402
from numba.extending import intrinsic  # noqa: E402

numba.config.CACHE_DIR = str(_CACHE) if _CACHE is not None else ""  # read as kernels are made
_jit = dict(cache=_CACHE is not None, error_model="numpy", nogil=True)
# one ray's kernels are inlined into the loops: a call would pass the scene's arrays by value,
# with a reference count per array, which cost more than the ray's arithmetic (measured)
_one_ray = dict(_jit, inline="always")


class Tree(NamedTuple):
    """A BVH (:class:`raykit.engine.bvh.BVH`, :func:`scene_tree`) as the kernels walk it, with
    the objects' own boxes it was built from, ``object_lower``, ``object_upper (K, 3)``."""

    lower: np.ndarray
    upper: np.ndarray
    children: np.ndarray
    first: np.ndarray
    count: np.ndarray
    order: np.ndarray
    object_lower: np.ndarray
    object_upper: np.ndarray


class Arrays(NamedTuple):
    """A scene as flat arrays for the kernels, in object index order (:mod:`raykit.scene`):
    spheres ``centers (S, 3)``, ``radii (S,)``, ``sphere_colors (S, 3)``
    (:class:`raykit.engine.arrays.SceneArrays`); billboards' ``corners (B, 3)`` (upper_left),
    normals ``n (B, 3)`` (a × b), ``alpha_axes``, ``beta_axes (B, 3)``
    (:attr:`raykit.billboards.Billboard.dual_axes`), flat ``board_colors (B, 3)``, and textures:
    ``texture_start (B,)`` (-1: none) into the texels of all textures, row by row, as
    :func:`raykit.billboards.colors_and_opacity` reads them: ``texel_colors (T, 3)``,
    ``texel_opaque (T,)``; ``texture_width``, ``texture_height (B,)``; the ``background (3,)``."""

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
    texel_colors: np.ndarray
    texel_opaque: np.ndarray
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
    return _one_kind(
        Arrays(
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
            *colors_and_opacity(np.concatenate(texels) if texels else np.zeros((0, 4), np.uint8)),
            np.asarray(scene.background, dtype=float),
        )
    )


def _one_kind(parts):
    """``parts`` (a NamedTuple) with every array C-contiguous, aligned and writeable, copied
    where it is not: numba compiles each kernel again, about 220 s here, for every new kind of
    array it is given, and a read-only one is another kind (a scene file's plain spheres come
    as read-only columns, :class:`raykit.spheres.SphereTable`). So every scene renders with
    the kernels the first compile made."""
    arrays = {
        name: np.require(value, requirements="CAW")
        for name, value in parts._asdict().items()
        if isinstance(value, np.ndarray)
    }
    return parts._replace(**arrays)


class Lights(NamedTuple):
    """What shading needs (:mod:`raykit.shading`), as arrays: ``shaded`` (anything beyond flat
    colours: :func:`raykit.shading.needs_shading`), ``lit`` (lights or ambient), ``shadows``
    (:func:`raykit.shading.casts_shadows`), ``max_depth``; per light ``point (L,)`` (False:
    directional), ``vectors (L, 3)`` (a point light's position, or a directional light's l, made
    by :func:`raykit.lights.toward_light`), intensity ``colors (L, 3)``; ``ambient (3,)``; per
    object the material table (:class:`raykit.materials.MaterialTable`) and whether it is
    ``shiny`` or a ``mirror (K,)``; the billboards' unit ``board_normals (B, 3)``."""

    shaded: bool
    lit: bool
    shadows: bool
    max_depth: int
    point: np.ndarray
    vectors: np.ndarray
    colors: np.ndarray
    ambient: np.ndarray
    diffuse: np.ndarray
    has_diffuse: np.ndarray
    specular: np.ndarray
    shininess: np.ndarray
    mirror: np.ndarray
    shiny: np.ndarray
    mirrors: np.ndarray
    board_normals: np.ndarray


def scene_lights(scene: Scene) -> Lights:
    """The scene's :class:`Lights`, from the reference's own functions and tables."""
    table = scene.materials
    point = np.array([isinstance(light, PointLight) for light in scene.lights], dtype=np.bool_)
    origin = np.zeros((1, 3))
    vectors = [
        np.asarray(light.position, float) if isinstance(light, PointLight)
        else toward_light(light, origin)[0][0]
        for light in scene.lights
    ]  # fmt: skip
    return _one_kind(
        Lights(
            needs_shading(scene),
            scene.lit,
            casts_shadows(scene),
            scene.max_depth,
            point,
            np.array(vectors, dtype=float).reshape(-1, 3),
            np.array([light.color for light in scene.lights], dtype=float).reshape(-1, 3),
            np.asarray(scene.ambient if scene.ambient is not None else np.zeros(3), dtype=float),
            table.diffuse.astype(float).reshape(-1, 3),
            table.has_diffuse,
            table.specular.reshape(-1, 3),
            table.shininess,
            table.mirror.reshape(-1, 3),
            table.specular.reshape(-1, 3).any(axis=1),
            table.mirror.reshape(-1, 3).any(axis=1),
            np.array([normalize(b.n) for b in scene.billboards], dtype=float).reshape(-1, 3),
        )
    )


_NO_TREE = Tree(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 2), np.int64),
                *[np.zeros(0, np.int64)] * 3, np.zeros((0, 3)), np.zeros((0, 3)))  # fmt: skip


def scene_tree(scene: Scene) -> Tree:
    """The scene's BVH, built by the numpy engine's own builder, as a :class:`Tree`."""
    bvh = BVH.build(scene)
    object_lower, object_upper = bvh.arrays.boxes
    return Tree(
        bvh.lower.astype(float).reshape(-1, 3),
        bvh.upper.astype(float).reshape(-1, 3),
        bvh.children.astype(np.int64).reshape(-1, 2),
        *(part.astype(np.int64) for part in (bvh.first, bvh.count, bvh.order)),
        object_lower.astype(float).reshape(-1, 3),
        object_upper.astype(float).reshape(-1, 3),
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
    :func:`~raykit.billboards.texel_indices`) for one hit: ``(r, g, b, opaque)``, the texel's
    colour and opacity as :func:`~raykit.billboards.colors_and_opacity` gave them
    (:func:`scene_arrays`)."""
    start = arrays.texture_start[board]
    if start < 0:
        colors = arrays.board_colors
        return colors[board, 0], colors[board, 1], colors[board, 2], True
    width = arrays.texture_width[board]
    height = arrays.texture_height[board]
    column = min(math.floor(alpha * width), width - 1)
    row = min(math.floor(beta * height), height - 1)
    texel = start + int(row) * width + int(column)
    colors = arrays.texel_colors
    return colors[texel, 0], colors[texel, 1], colors[texel, 2], arrays.texel_opaque[texel]


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


# objects in a scene up to which a shadow or mirror ray tests each object, not the tree's
# boxes: mirror_balls's 5 render about 8% faster so (prepared, in turns: 8.0 -> 7.4 ms)
DIRECT_HITS = 8


@njit(**_one_ray)
def nearest_hit(arrays, tree, stack, o0, o1, o2, d0, d1, d2, t_max, any_blocker=False):
    """Repeats :func:`raykit.render.cast` for one ray, through the BVH: ``(index, t, r, g, b)``,
    the nearest opaque hit with t > 0 (the lower index on a tie), or (-1, inf, background).
    Hits at t > t_max may be left out (shadow rays). In a scene of :data:`DIRECT_HITS` objects
    or fewer each object is tested, as if all were one leaf, and no box is. ``any_blocker``:
    a shadow ray asks only whether some opaque hit lies before t_max
    (:func:`raykit.shadows.in_shadow` compares the nearest hit's t with it), so the search
    stops at the first such hit, whose t < t_max answers as the nearest's would. ``stack``:
    room for the nodes still to visit and where the ray enters them, ``(STACK,)`` ints and
    floats (:func:`new_stack`), reused from ray to ray. A child's box is tested once, when its
    parent is left, and skipped when taken from the stack if the nearest hit found meanwhile
    lies before it: the nodes visited are those a test at each visit would visit, with one slab
    test fewer per node."""
    background = arrays.background
    best, best_t = -1, np.inf
    r, g, b = background[0], background[1], background[2]
    objects = len(tree.order)  # the tree holds each of the scene's objects once
    if objects == 0:
        return best, best_t, r, g, b
    i0, i1, i2 = 1.0 / d0, 1.0 / d1, 1.0 / d2  # ±inf along an axis the ray does not move
    lower, upper = tree.lower, tree.upper
    nodes, nears = stack
    if objects <= DIRECT_HITS:
        nodes[0], nears[0] = -1, -np.inf  # -1: every object, as one leaf with no box
    else:
        entered, near = enters(o0, o1, o2, i0, i1, i2, lower, upper, 0, t_max)
        if not entered:
            return best, best_t, r, g, b
        nodes[0], nears[0] = 0, near
    top = 1
    while top > 0:  # each node on the stack was entered, at nears[top]
        top -= 1
        node = nodes[top]
        reach = min(best_t, t_max)
        if nears[top] > reach:
            continue  # a box that starts beyond the nearest hit holds no nearer one
        if node < 0:
            first, count = 0, objects
        else:
            left = tree.children[node, 0]
            if left >= 0:
                right = tree.children[node, 1]
                in_left, near_left = enters(o0, o1, o2, i0, i1, i2, lower, upper, left, reach)
                in_right, near_right = enters(o0, o1, o2, i0, i1, i2, lower, upper, right, reach)
                if in_left and in_right:  # the nearer child is searched first: pushed last
                    if near_left <= near_right:
                        nodes[top], nears[top] = right, near_right
                        nodes[top + 1], nears[top + 1] = left, near_left
                    else:
                        nodes[top], nears[top] = left, near_left
                        nodes[top + 1], nears[top + 1] = right, near_right
                    top += 2
                elif in_left:
                    nodes[top], nears[top] = left, near_left
                    top += 1
                elif in_right:
                    nodes[top], nears[top] = right, near_right
                    top += 1
                continue
            first, count = tree.first[node], tree.count[node]
        # one call site: offer is compiled in once (a second loop for DIRECT_HITS, calling
        # offer apart, rendered mirror_balls 4% faster but took a minute more to compile)
        for k in range(first, first + count):
            best, best_t, r, g, b = offer(
                arrays, tree.order[k], o0, o1, o2, d0, d1, d2, best, best_t, r, g, b
            )
            if any_blocker and best_t < t_max:
                return best, best_t, r, g, b
    return best, best_t, r, g, b


@njit(**_one_ray)
def new_stack():
    """Room for :func:`nearest_hit`'s nodes still to visit: ``(nodes (STACK,), nears (STACK,))``."""
    return np.empty(STACK, dtype=np.int64), np.empty(STACK)


@njit(**_one_ray)
def viewing_ray(camera, x, y):
    """Repeats :func:`raykit.camera.rays_through` for one image point (x, y): ``(o0, o1, o2,
    d0, d1, d2)``. ``camera`` is the eye e, u, v, w, then -Wp/2, Wp/width, Hp/2, Hp/height, d
    and whether it is orthographic (1.0) or not (0.0), as 18 numbers: :func:`camera_tuple`."""
    e0, e1, e2, u0, u1, u2, v0, v1, v2, w0, w1, w2, left, across, top, down, d, ortho = camera
    s = left + x * across
    t = top - y * down
    p0 = s * u0 + t * v0
    p1 = s * u1 + t * v1
    p2 = s * u2 + t * v2
    if ortho != 0:  # orthographic: origin e + s·u + t·v, direction -w
        return e0 + p0, e1 + p1, e2 + p2, -w0, -w1, -w2
    x0 = p0 - d * w0
    x1 = p1 - d * w1
    x2 = p2 - d * w2
    length = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    return e0, e1, e2, x0 / length, x1 / length, x2 / length


@njit(**_one_ray)
def surface_point(arrays, lights, o0, o1, o2, d0, d1, d2, hit, t):
    """Repeats :func:`raykit.surfaces.surface_points` for one ray and its hit (object ``hit`` at
    ``t``): ``(p0, p1, p2, n0, n1, n2, error)``, the point p = o + t·d, the unit normal n on the
    side the ray arrives at, and the point's rounding bound."""
    p0, p1, p2 = o0 + t * d0, o1 + t * d1, o2 + t * d2
    spheres = len(arrays.radii)
    if hit < spheres:  # raykit.spheres.sphere_normals
        R = arrays.radii[hit]
        centers = arrays.centers
        n0 = (p0 - centers[hit, 0]) / R
        n1 = (p1 - centers[hit, 1]) / R
        n2 = (p2 - centers[hit, 2]) / R
    else:  # raykit.billboards.billboard_normals: the side the ray arrives at
        normals, board = lights.board_normals, hit - spheres
        m0, m1, m2 = normals[board, 0], normals[board, 1], normals[board, 2]
        facing = -1.0 if d0 * m0 + d1 * m1 + d2 * m2 > 0 else 1.0
        n0, n1, n2 = facing * m0, facing * m1, facing * m2
    error = EPS * (max(abs(o0), abs(o1), abs(o2)) + t)
    return p0, p1, p2, n0, n1, n2, error


@njit(**_one_ray)
def toward_point_light(v0, v1, v2, p0, p1, p2):
    """Repeats :func:`raykit.lights.toward_light` for a point light at v: the unit l from p."""
    to0, to1, to2 = v0 - p0, v1 - p1, v2 - p2
    distance = math.sqrt(to0 * to0 + to1 * to1 + to2 * to2)
    return to0 / distance, to1 / distance, to2 / distance


@njit(**_one_ray)
def off_surface(p0, p1, p2, n0, n1, n2, error):
    """Repeats :meth:`raykit.surfaces.SurfacePoints.start` for a ray leaving p on n's side."""
    epsilon = OFFSET_FACTOR * error
    return p0 + epsilon * n0, p1 + epsilon * n1, p2 + epsilon * n2


@njit(**_one_ray)
def point_light_reach(v0, v1, v2, s0, s1, s2):
    """Repeats :func:`raykit.shadows.light_reach` for a point light at v and a shadow ray from
    s: how far along the ray a blocker counts."""
    to0, to1, to2 = v0 - s0, v1 - s1, v2 - s2
    distance = math.sqrt(to0 * to0 + to1 * to1 + to2 * to2)
    largest = max(abs(s0), abs(s1), abs(s2))
    return distance - OFFSET_FACTOR * EPS * (largest + distance)


@njit(**_one_ray)
def highlight(n0, n1, n2, l0, l1, l2, d0, d1, d2, p):
    """Repeats the power in :func:`raykit.shading.blinn_phong`, max(0, n·h)^p with
    h = (l + v)/|l + v| and v = -d, or -1.0 where l + v = 0 (no highlight, as
    :func:`raykit.shading.surface_color` says). The one operation that may differ from the
    reference: the power is the C library's pow here and numpy's own (vectorised) power there;
    they differ by at most one unit in the last place, on a few per cent of highlight points
    (measured), which no 8-bit pixel shows (tests/test_compiled.py bounds it)."""
    v0, v1, v2 = -d0, -d1, -d2
    if not (l0 + v0 != 0 or l1 + v1 != 0 or l2 + v2 != 0):
        return -1.0
    h0, h1, h2 = l0 + v0, l1 + v1, l2 + v2
    length = math.sqrt(h0 * h0 + h1 * h1 + h2 * h2)
    n_dot_h = n0 * (h0 / length) + n1 * (h1 / length) + n2 * (h2 / length)
    return (n_dot_h if n_dot_h > 0 else 0.0) ** p


@njit(**_one_ray)
def surface_color(
    arrays, tree, lights, stack, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error, r, g, b
):
    """Repeats :func:`raykit.shading.surface_color` for one hit: object ``hit`` at point p
    with unit normal n, seen along d, its flat colour (r, g, b); ``error`` is the point's
    rounding bound (:func:`surface_point`). Shadow rays (:mod:`raykit.shadows`) walk the tree.
    A tile's viewing rays are shaded in lanes instead (:func:`light_lanes`), the same
    operations in the same order for each."""
    if not lights.lit:
        return r, g, b
    if lights.has_diffuse[hit]:
        k0, k1, k2 = lights.diffuse[hit, 0], lights.diffuse[hit, 1], lights.diffuse[hit, 2]
    else:
        k0, k1, k2 = r, g, b
    ambient = lights.ambient
    total0, total1, total2 = k0 * ambient[0], k1 * ambient[1], k2 * ambient[2]
    vectors, intensity = lights.vectors, lights.colors
    for j in range(len(lights.point)):
        v0, v1, v2 = vectors[j, 0], vectors[j, 1], vectors[j, 2]
        if lights.point[j]:  # raykit.lights.toward_light
            l0, l1, l2 = toward_point_light(v0, v1, v2, p0, p1, p2)
        else:
            l0, l1, l2 = v0, v1, v2
        n_dot_l = n0 * l0 + n1 * l1 + n2 * l2
        if not n_dot_l > 0:
            continue
        if lights.shadows:  # raykit.shadows.light_reach and in_shadow
            s0, s1, s2 = off_surface(p0, p1, p2, n0, n1, n2, error)
            reach = point_light_reach(v0, v1, v2, s0, s1, s2) if lights.point[j] else np.inf
            _, blocker, _, _, _ = nearest_hit(
                arrays, tree, stack, s0, s1, s2, l0, l1, l2, reach, True
            )
            if blocker < reach:
                continue
        total0 += k0 * intensity[j, 0] * n_dot_l  # raykit.shading.lambert
        total1 += k1 * intensity[j, 1] * n_dot_l
        total2 += k2 * intensity[j, 2] * n_dot_l
        if lights.shiny[hit]:
            power = highlight(n0, n1, n2, l0, l1, l2, d0, d1, d2, lights.shininess[hit])
            if power >= 0:  # raykit.shading.blinn_phong
                ks = lights.specular
                total0 += ks[hit, 0] * intensity[j, 0] * power
                total1 += ks[hit, 1] * intensity[j, 1] * power
                total2 += ks[hit, 2] * intensity[j, 2] * power
    return total0, total1, total2


@njit(**_one_ray)
def bounce_on(arrays, tree, lights, stack, depth, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error,
              c0, c1, c2, w0, w1, w2):  # fmt: skip
    """The rest of :func:`shade_ray` after the surface at ``depth`` (object ``hit`` at p, normal
    n, seen along d, rounding bound ``error``) has added its colour to the pixel's (c0, c1, c2):
    mirror rays (:func:`raykit.mirrors.reflect`, started off the surface) up to max_depth, each
    surface's colour weighted by the mirrors' km on the way (w)."""
    while depth < lights.max_depth and lights.mirrors[hit]:
        twice = 2.0 * (d0 * n0 + d1 * n1 + d2 * n2)
        d0, d1, d2 = d0 - twice * n0, d1 - twice * n1, d2 - twice * n2
        side = 1.0 if n0 * d0 + n1 * d1 + n2 * d2 >= 0 else -1.0
        offset = side * (OFFSET_FACTOR * error)
        o0, o1, o2 = p0 + offset * n0, p1 + offset * n1, p2 + offset * n2
        km = lights.mirror
        w0, w1, w2 = w0 * km[hit, 0], w1 * km[hit, 1], w2 * km[hit, 2]
        hit, t, r, g, b = nearest_hit(arrays, tree, stack, o0, o1, o2, d0, d1, d2, np.inf)
        depth += 1
        if hit < 0:
            return c0 + w0 * r, c1 + w1 * g, c2 + w2 * b  # the background
        p0, p1, p2, n0, n1, n2, error = surface_point(arrays, lights, o0, o1, o2, d0, d1, d2,
                                                      hit, t)  # fmt: skip
        s0, s1, s2 = surface_color(
            arrays, tree, lights, stack, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error, r, g, b
        )
        c0, c1, c2 = c0 + w0 * s0, c1 + w1 * s1, c2 + w2 * s2
    return c0, c1, c2


@njit(**_one_ray)
def shade_ray(arrays, tree, lights, stack, o0, o1, o2, d0, d1, d2, hit, t, r, g, b):
    """Repeats :func:`raykit.shading.shade` for one viewing ray and its nearest hit: the surface
    point (:func:`surface_point`), its colour (:func:`surface_color`), and mirror rays up to
    max_depth (:func:`bounce_on`)."""
    if hit < 0:
        return 0.0 + 1.0 * r, 0.0 + 1.0 * g, 0.0 + 1.0 * b  # the background, weighted 1
    p0, p1, p2, n0, n1, n2, error = surface_point(arrays, lights, o0, o1, o2, d0, d1, d2, hit, t)
    s0, s1, s2 = surface_color(
        arrays, tree, lights, stack, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2, error, r, g, b
    )
    c0, c1, c2 = 0.0 + 1.0 * s0, 0.0 + 1.0 * s1, 0.0 + 1.0 * s2  # weighted 1, added to nothing
    return bounce_on(arrays, tree, lights, stack, 0, hit, p0, p1, p2, n0, n1, n2, d0, d1, d2,
                     error, c0, c1, c2, 1.0, 1.0, 1.0)  # fmt: skip


@njit(**_jit)
def bin_by_tile(bounds, closest, by_distance, tiles_x, tiles_y, size):
    """Each tile's objects, for primary rays: the objects ``by_distance (K,)`` (nearest first)
    whose screen rectangle ``bounds (K, 4)`` (x0, x1, y0, y1; NaN: never seen,
    :func:`raykit.engine.screen_bounds.scene_bounds`) meets the tile of ``size`` x ``size``
    pixels. Returns ``start (tiles + 1,)``, ``objects (E,)``: tile k's are
    objects[start[k]:start[k+1]], nearest first; and each of those entries' rectangle and
    ``closest`` t, ``entries (E, 5)``, kept beside it so that a pixel reads its tile's list
    straight through."""
    count = np.zeros(tiles_x * tiles_y + 1, dtype=np.int64)
    for fill in (False, True):  # count, then fill
        if fill:
            start = np.cumsum(count)
            cursor = start[:-1].copy()
            objects = np.empty(start[-1], dtype=np.int64)
            entries = np.empty((start[-1], 5))
        else:
            start = count
            cursor = count[:0]
            objects = np.empty(0, dtype=np.int64)
            entries = np.empty((0, 5))
        for obj in by_distance:
            x0, x1, y0, y1 = bounds[obj, 0], bounds[obj, 1], bounds[obj, 2], bounds[obj, 3]
            if not (x0 <= x1 and y0 <= y1):
                continue
            left, right = max(0, int(x0 // size)), min(tiles_x - 1, int(x1 // size))
            top, bottom = max(0, int(y0 // size)), min(tiles_y - 1, int(y1 // size))
            for ty in range(top, bottom + 1):
                for tx in range(left, right + 1):
                    tile = ty * tiles_x + tx
                    if fill:
                        k = cursor[tile]
                        objects[k] = obj
                        entries[k, 0], entries[k, 1], entries[k, 2], entries[k, 3] = x0, x1, y0, y1
                        entries[k, 4] = closest[obj]
                        cursor[tile] += 1
                    else:
                        count[tile + 1] += 1
    return start, objects, entries


class Tiles(NamedTuple):
    """The primary rays' skip (:func:`screen_tiles`): tile k (``size`` x ``size`` pixels,
    ``tiles_x`` to a row) lists the objects ``objects[start[k]:start[k + 1]]``, nearest first,
    each with its screen rectangle and closest t in ``entries (E, 5)``: (x0, x1, y0, y1,
    closest); a tile's rays go in ``packets`` (:func:`primary_rays`) or one at a time."""

    start: np.ndarray
    objects: np.ndarray
    entries: np.ndarray
    tiles_x: int
    size: int
    packets: bool


HOLDING_CHUNK = 8  # entries of a tile's list that primary_ray checks at a time


@njit(**_one_ray)
def primary_ray(arrays, tiles, camera, x, y, tile, holding):
    """:func:`nearest_hit` for the viewing ray through image point (x, y), from the list of its
    tile (:func:`screen_tiles`; -1: the tile is found from x and y): only the objects whose
    screen rectangle holds the point (as :meth:`raykit.engine.tiles.Region.holding` decides),
    nearest first, until the next can only be farther than the hit found. The ray is made at
    the first rectangle that holds the point: if none does, it would see the background, and is
    not made at all (as in :meth:`raykit.engine.regions.Plan.viewing_rays`). Returns ``(made,
    index, t, r, g, b, o0, o1, o2, d0, d1, d2)`` (the ray 0 if not made).

    The list is read HOLDING_CHUNK entries at a time: first which of them hold the point, into
    ``holding (HOLDING_CHUNK,)``, with no branch, then those in order. In a crowded picture an
    entry holds the point one time in two or three, and a branch per entry, guessed wrong that
    often, cost more than the checks (about a fifth of sphereflake 6's render, measured). The
    objects offered are the same, in the same order: the lists are sorted by closest t, which
    is not NaN where the scene's numbers are finite (as :mod:`raykit.io` checks every scene
    file's), and the nearest hit only comes nearer, so an entry checked past the one a scan
    entry by entry stops at can only be farther than the hit, and is not offered either
    (tests/test_compiled.py compares the two scans)."""
    size, entries, objects = tiles.size, tiles.entries, tiles.objects
    background = arrays.background
    best, best_t = -1, np.inf
    r, g, b = background[0], background[1], background[2]
    made = False
    o0, o1, o2, d0, d1, d2 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if tile < 0:
        tile = (int(y) // size) * tiles.tiles_x + int(x) // size
    first, end = tiles.start[tile], tiles.start[tile + 1]
    while first < end:
        stop = min(end, first + HOLDING_CHUNK)
        held = 0
        for k in range(first, stop):  # & not `and`: no branch
            holding[held] = k
            held += (
                (entries[k, 0] <= x)
                & (x <= entries[k, 1])
                & (entries[k, 2] <= y)
                & (y <= entries[k, 3])
            )
        for i in range(held):
            k = holding[i]
            if entries[k, 4] > best_t:
                break  # every object from here on is farther than the hit
            if not made:
                o0, o1, o2, d0, d1, d2 = viewing_ray(camera, x, y)
                made = True
            best, best_t, r, g, b = offer(
                arrays, objects[k], o0, o1, o2, d0, d1, d2, best, best_t, r, g, b
            )
        if entries[stop - 1, 4] > best_t:
            break
        first = stop
    return made, best, best_t, r, g, b, o0, o1, o2, d0, d1, d2


@njit(**_one_ray)
def primary_rays(arrays, tiles, camera, tile, n, xy, rays, best, best_t, colors, made, alive, ts):
    """:func:`primary_ray` for the ``n`` image points of ``lanes`` at once, all in ``tile``: a
    packet of rays, each a lane of arrays (as :func:`trace` makes them: points ``xy (2, L)`` in,
    ``rays (6, L)``, ``best (L,)``, ``best_t``, ``colors (3, L)``, ``made`` out; ``alive``,
    ``ts`` room). The tile's objects are taken in turn, and each is tested against
    every lane with one loop of :func:`hit_sphere` that the compiler turns into vector
    instructions (8 lanes at a time with AVX-512); masks then keep, for each lane, only what
    :func:`primary_ray` would: a lane whose rectangle does not hold its point, or that has
    stopped (its next object can only be farther than its hit), takes nothing from the test.
    So each lane offers the same objects in the same order as :func:`primary_ray` and gets the
    same bits; the other lanes' answers are computed and thrown away, which costs less than a
    branch per ray when the tile's list is short. Billboards are offered lane by lane.
    Every lane's ray is made (a lane that no rectangle holds is not ``made``, as in
    :func:`primary_ray`, and its ray is not used)."""
    background = arrays.background
    for i in range(n):
        rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i], rays[5, i] = viewing_ray(
            camera, xy[0, i], xy[1, i]
        )
    for i in range(n):
        best[i], best_t[i] = -1, np.inf
        colors[0, i], colors[1, i], colors[2, i] = background[0], background[1], background[2]
        alive[i], made[i] = True, False
    spheres = len(arrays.radii)
    entries, objects = tiles.entries, tiles.objects
    centers, radii, sphere_colors = arrays.centers, arrays.radii, arrays.sphere_colors
    for k in range(tiles.start[tile], tiles.start[tile + 1]):
        closest = entries[k, 4]
        x0, x1, y0, y1 = entries[k, 0], entries[k, 1], entries[k, 2], entries[k, 3]
        obj = objects[k]
        alive_lanes = 0
        if obj < spheres:
            c0, c1, c2, R = centers[obj, 0], centers[obj, 1], centers[obj, 2], radii[obj]
            r, g, b = sphere_colors[obj, 0], sphere_colors[obj, 1], sphere_colors[obj, 2]
            for i in range(n):  # the vector loop: it writes one array only
                ts[i] = hit_sphere(
                    rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i], rays[5, i],
                    c0, c1, c2, R,
                )  # fmt: skip
            for i in range(n):  # offer's rule, with masks
                nearest = best_t[i]
                still = alive[i] & (closest <= nearest)
                x, y = xy[0, i], xy[1, i]
                holds = still & (x0 <= x) & (x <= x1) & (y0 <= y) & (y <= y1)
                t = ts[i]
                nearer = holds & ((t < nearest) | ((t == nearest) & (t < np.inf) & (obj < best[i])))
                if nearer:
                    best[i], best_t[i] = obj, t
                    colors[0, i], colors[1, i], colors[2, i] = r, g, b
                made[i] = made[i] | holds
                alive[i] = still
                alive_lanes += still
        else:
            for i in range(n):
                still = alive[i] and closest <= best_t[i]
                alive[i] = still
                alive_lanes += still
                x, y = xy[0, i], xy[1, i]
                if still and x0 <= x and x <= x1 and y0 <= y and y <= y1:
                    made[i] = True
                    best[i], best_t[i], colors[0, i], colors[1, i], colors[2, i] = offer(
                        arrays, obj, rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i],
                        rays[5, i], best[i], best_t[i], colors[0, i], colors[1, i], colors[2, i],
                    )  # fmt: skip
        if alive_lanes == 0:
            break


# ---- shadow rays' skip: each tile's objects that may cast a shadow on what it sees -------------


SHADOW_CANDIDATES = 16  # objects a tile lists per light; with more, its shadow rays walk the BVH
DIRECT_LISTS = 64  # objects in a scene up to which the lists test each object, not the tree's
# nodes: at 14 objects, 0.09 against 1.1 microseconds a list (classic_lit, one core)
CULL_MARGIN = 1e-9  # of the scene's largest coordinate: rounding that the cull leaves room for


@njit(**_one_ray)
def extent(lo0, lo1, lo2, hi0, hi1, hi2, e0, e1, e2):
    """``(lowest, highest)``: where the points of the box lo..hi lie along axis e."""
    x0, x1, y0, y1, z0, z1 = lo0 * e0, hi0 * e0, lo1 * e1, hi1 * e1, lo2 * e2, hi2 * e2
    return min(x0, x1) + min(y0, y1) + min(z0, z1), max(x0, x1) + max(y0, y1) + max(z0, z1)


@njit(**_one_ray)
def box_extent(lower, upper, i, e0, e1, e2):
    """:func:`extent` of box i of ``lower``, ``upper (M, 3)``."""
    return extent(
        lower[i, 0], lower[i, 1], lower[i, 2], upper[i, 0], upper[i, 1], upper[i, 2], e0, e1, e2
    )


@njit(**_one_ray)
def box_apart(volume, lower, upper, i) -> bool:
    """Whether box i (of ``lower``, ``upper (M, 3)``) lies wholly beyond the shadow volume
    along one of its axes (:func:`shadow_volume`): x, y and z first, where a box's extent is
    its own sides."""
    for k in range(3):
        if upper[i, k] < volume[k, 3] or lower[i, k] > volume[k, 4]:
            return True
    for row in range(3, 6):
        low, high = box_extent(lower, upper, i, volume[row, 0], volume[row, 1], volume[row, 2])
        if high < volume[row, 3] or low > volume[row, 4]:
            return True
    return False


@njit(**_one_ray)
def sphere_apart(volume, centers, radii, i) -> bool:
    """Whether sphere i lies wholly beyond the shadow volume along one of its axes."""
    R = radii[i]
    for k in range(3):
        if centers[i, k] + R < volume[k, 3] or centers[i, k] - R > volume[k, 4]:
            return True
    for row in range(3, 6):
        c = centers[i, 0] * volume[row, 0] + centers[i, 1] * volume[row, 1]
        c += centers[i, 2] * volume[row, 2]
        if c + R < volume[row, 3] or c - R > volume[row, 4]:
            return True
    return False


@njit(**_one_ray)
def shadow_volume(lights, j, box, pad, scale, volume):
    """Fills ``volume (6, 5)``, rows (e0, e1, e2, lowest, highest): six axes e, and along each
    the interval that holds every shadow ray toward light j from a point of the box ``box (2,
    3)`` (lower and upper corners) widened by ``pad``: a directional light's rays sweep the box
    along l to infinity; a point light's lie in the hull of the box and the light, the light
    too widened by ``pad`` (a ray from s = p + ε·n takes the direction from p, so it passes the
    light at ε from it). The axes: x, y and z
    (in rows 0, 1, 2, as :func:`box_apart` reads them), two across the direction to the light,
    and that direction. The box and each interval are
    widened by CULL_MARGIN x the largest coordinate of the scene (``scale``), the box or the
    light."""
    point = lights.point[j]
    v0, v1, v2 = lights.vectors[j, 0], lights.vectors[j, 1], lights.vectors[j, 2]
    largest = scale
    for k in range(3):  # (scalars: an array expression here would allocate, once per tile)
        largest = max(largest, abs(box[0, k]), abs(box[1, k]))
    if point:
        largest = max(largest, abs(v0), abs(v1), abs(v2))
    margin = CULL_MARGIN * largest
    lo0, lo1, lo2 = box[0, 0] - pad - margin, box[0, 1] - pad - margin, box[0, 2] - pad - margin
    hi0, hi1, hi2 = box[1, 0] + pad + margin, box[1, 1] + pad + margin, box[1, 2] + pad + margin
    if point:  # from the box's centre toward the light
        m0, m1, m2 = v0 - (lo0 + hi0) / 2, v1 - (lo1 + hi1) / 2, v2 - (lo2 + hi2) / 2
    else:
        m0, m1, m2 = v0, v1, v2
    length = math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
    if not length > 0:  # any axis separates as truly; this one only less tightly
        m0, m1, m2, length = 1.0, 0.0, 0.0, 1.0
    m0, m1, m2 = m0 / length, m1 / length, m2 / length
    if abs(m0) < 0.6:  # a, b across m: m x (1, 0, 0), or m x (0, 1, 0) if m is near x; m x a
        a0, a1, a2 = 0.0, m2, -m1
    else:
        a0, a1, a2 = -m2, 0.0, m0
    length = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    a0, a1, a2 = a0 / length, a1 / length, a2 / length
    b0, b1, b2 = m1 * a2 - m2 * a1, m2 * a0 - m0 * a2, m0 * a1 - m1 * a0
    axes = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (a0, a1, a2), (b0, b1, b2),
            (m0, m1, m2))  # fmt: skip
    for row in range(6):
        e0, e1, e2 = axes[row]
        low, high = extent(lo0, lo1, lo2, hi0, hi1, hi2, e0, e1, e2)
        toward = v0 * e0 + v1 * e1 + v2 * e2
        if point:
            low, high = min(low, toward - pad), max(high, toward + pad)
        elif row != 3 and row != 4 and toward > 0:  # along l the rays go on for ever
            high = np.inf
        elif row != 3 and row != 4 and toward < 0:
            low = -np.inf
        volume[row, 0], volume[row, 1], volume[row, 2] = e0, e1, e2
        volume[row, 3], volume[row, 4] = low - margin, high + margin


@njit(**_one_ray)
def candidate(arrays, tree, volume, obj, candidates, j, count) -> int:
    """Adds object ``obj`` to light j's ``candidates`` unless it is apart from the shadow volume
    (a sphere: itself; a billboard: its box): the new count, or -1 past SHADOW_CANDIDATES."""
    if obj < len(arrays.radii):
        apart = sphere_apart(volume, arrays.centers, arrays.radii, obj)
    else:
        apart = box_apart(volume, tree.object_lower, tree.object_upper, obj)
    if apart:
        return count
    if count == SHADOW_CANDIDATES:
        return -1
    candidates[j, count] = obj
    return count + 1


@njit(**_one_ray)
def shadow_candidates(arrays, tree, volume, nodes, candidates, j) -> int:
    """Light j's candidates: the objects whose boxes (a sphere: itself) are not apart from the
    shadow volume (:func:`shadow_volume`), into ``candidates[j]``; returns how many, or -1 if
    more than SHADOW_CANDIDATES (then the shadow rays walk the tree themselves). In a scene of
    DIRECT_LISTS objects or fewer each object is tested; in a larger one, the tree is walked,
    leaving every node whose box is apart. ``nodes (STACK,)``."""
    objects = len(tree.order)
    count = 0
    if objects <= DIRECT_LISTS:
        for obj in range(objects):
            count = candidate(arrays, tree, volume, obj, candidates, j, count)
            if count < 0:
                return -1
        return count
    nodes[0] = 0
    top = 1
    while top > 0:
        top -= 1
        node = nodes[top]
        if box_apart(volume, tree.lower, tree.upper, node):
            continue
        if tree.children[node, 0] >= 0:
            nodes[top], nodes[top + 1] = tree.children[node, 1], tree.children[node, 0]
            top += 2
            continue
        for k in range(tree.first[node], tree.first[node] + tree.count[node]):
            count = candidate(arrays, tree, volume, tree.order[k], candidates, j, count)
            if count < 0:
                return -1
    return count


@njit(**_one_ray)
def shadow_lists(arrays, tree, lights, stack, box, pad, volume, candidates, counts):
    """Each light j's :func:`shadow_candidates` for the shadow rays from the surface points in
    ``box (2, 3)`` (lower, upper corners; empty if lower > upper), which start within ``pad``
    of them, into ``candidates[j]`` (L x
    SHADOW_CANDIDATES) and ``counts (L,)``, with room for a shadow volume ``volume (6, 5)``.

    Why the answers stay the reference's. A point is in shadow if some opaque hit lies before
    the light (:func:`raykit.shadows.in_shadow`): whichever object gives it, the answer is the
    same, so an object may be left out if no shadow ray can hit it. A ray from a point of the
    box toward light j lies in its volume (:func:`shadow_volume`), and where the reference finds
    a hit is a point of the ray and, up to rounding, of the object: that rounding, a few units
    in the last place of the scene's coordinates, is a millionth of the margin the volume is
    widened by, so an object the volume is apart from is never hit."""
    counts[:] = -1
    if not box[0, 0] <= box[1, 0] or len(tree.order) == 0:
        return
    scale = 0.0  # the largest coordinate of the root box
    for k in range(3):
        scale = max(scale, abs(tree.lower[0, k]), abs(tree.upper[0, k]))
    nodes, _ = stack
    for j in range(len(counts)):
        shadow_volume(lights, j, box, pad, scale, volume)
        counts[j] = shadow_candidates(arrays, tree, volume, nodes, candidates, j)


@njit(**_one_ray)
def new_lanes(count):
    """Room for shading ``count`` viewing rays in lanes (:func:`surface_lanes`,
    :func:`light_lanes`), each a column, as the tuple ``(p, n, error, k, total, l, n_dot_l, s,
    reach, t, lit)``: the surface point ``p (3, N)``, its normal ``n (3, N)`` and rounding bound
    ``error (N,)`` (:func:`surface_point`), the colour k that light scales ``k (3, N)`` and the
    colour so far ``total (3, N)``; toward the light at hand, ``l (3, N)``, ``n_dot_l (N,)``,
    the shadow ray's start ``s (3, N)`` and ``reach (N,)``, room ``t (N,)``, and whether the
    light reaches the point, ``lit (N,)``. A plain tuple: inside a parallel loop, writes
    through a NamedTuple's fields are lost (numba issue #7135, open in numba 0.68.1)."""
    return (np.empty((3, count)), np.empty((3, count)), np.empty(count), np.empty((3, count)),
            np.empty((3, count)), np.empty((3, count)), np.empty(count), np.empty((3, count)),
            np.empty(count), np.empty(count), np.empty(count, dtype=np.bool_))  # fmt: skip


@njit(**_one_ray)
def surface_lanes(arrays, lights, rays, best, best_t, colors, count, lanes, box):
    """The first part of :func:`surface_color` for each of ``count`` viewing rays ``rays (6,
    N)`` (origins, then directions) with a hit (``best`` >= 0, at ``best_t``; flat colours
    ``colors (3, N)``): its surface point, normal and rounding bound (:func:`surface_point`),
    k and the ambient term (in an unlit scene, the flat colour), into ``lanes``; and the box
    of the points into ``box (2, 3)`` (empty: lower > upper). Returns the largest rounding
    bound."""
    p, n, error_of, k, total = lanes[0], lanes[1], lanes[2], lanes[3], lanes[4]
    box[0, :], box[1, :] = np.inf, -np.inf
    largest = 0.0
    ambient = lights.ambient
    for i in range(count):
        hit = best[i]
        if hit < 0:  # zeros, not whatever the room held: arithmetic on them is thrown away
            for row in range(3):
                p[row, i], n[row, i] = 0.0, 0.0
            error_of[i] = 0.0
            continue
        p0, p1, p2, n0, n1, n2, error = surface_point(
            arrays, lights, rays[0, i], rays[1, i], rays[2, i], rays[3, i], rays[4, i],
            rays[5, i], hit, best_t[i],
        )  # fmt: skip
        p[0, i], p[1, i], p[2, i] = p0, p1, p2
        n[0, i], n[1, i], n[2, i] = n0, n1, n2
        error_of[i] = error
        if lights.has_diffuse[hit]:
            k0, k1, k2 = lights.diffuse[hit, 0], lights.diffuse[hit, 1], lights.diffuse[hit, 2]
        else:
            k0, k1, k2 = colors[0, i], colors[1, i], colors[2, i]
        k[0, i], k[1, i], k[2, i] = k0, k1, k2
        if lights.lit:
            total[0, i] = k0 * ambient[0]
            total[1, i] = k1 * ambient[1]
            total[2, i] = k2 * ambient[2]
        else:  # an unlit scene's surface colour is its flat colour
            total[0, i], total[1, i] = colors[0, i], colors[1, i]
            total[2, i] = colors[2, i]
        box[0, 0], box[1, 0] = min(box[0, 0], p0), max(box[1, 0], p0)
        box[0, 1], box[1, 1] = min(box[0, 1], p1), max(box[1, 1], p1)
        box[0, 2], box[1, 2] = min(box[0, 2], p2), max(box[1, 2], p2)
        largest = max(largest, error)
    return largest


@njit(**_jit)  # called once a job: compiled apart, which keeps trace's compile shorter
def light_lanes(arrays, tree, lights, stack, rays, best, count, lanes, candidates, counts):
    """The lights' part of :func:`surface_color` for ``count`` surface points in ``lanes``
    (:func:`surface_lanes`; those of ``best`` >= 0), seen along the directions in ``rays (6,
    N)``, light by light, each step for all points at once: l and n·l; whether the light
    reaches the point (its shadow ray, against light j's ``candidates[j, :counts[j]]``
    (:func:`shadow_lists`), or walking the tree where counts[j] is -1); the Lambert term; the
    highlight. Each point's operations are :func:`surface_color`'s, in its order, so its bits
    are the same; a step that is the same for every point (l, n·l, the start of a shadow ray,
    a sphere or a billboard's plane tested against every shadow ray, the Lambert term, kept or
    not) is one loop the compiler turns into vector instructions, 8 points at a time with
    AVX-512. A point with no hit or facing away from the light takes nothing from them."""
    spheres = len(arrays.radii)
    centers, radii, corners, planes = arrays.centers, arrays.radii, arrays.corners, arrays.n
    p, n, error, k, total, l, n_dot_l, s, reach, t, lit = lanes
    for j in range(len(lights.point)):
        v0, v1, v2 = lights.vectors[j, 0], lights.vectors[j, 1], lights.vectors[j, 2]
        if lights.point[j]:  # raykit.lights.toward_light; the shadow rays' start and reach
            for i in range(count):
                l[0, i], l[1, i], l[2, i] = toward_point_light(v0, v1, v2, p[0, i], p[1, i],
                                                               p[2, i])  # fmt: skip
                s[0, i], s[1, i], s[2, i] = off_surface(
                    p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error[i]
                )
                reach[i] = point_light_reach(v0, v1, v2, s[0, i], s[1, i], s[2, i])
        else:
            for i in range(count):
                l[0, i], l[1, i], l[2, i] = v0, v1, v2
                s[0, i], s[1, i], s[2, i] = off_surface(
                    p[0, i], p[1, i], p[2, i], n[0, i], n[1, i], n[2, i], error[i]
                )
                reach[i] = np.inf
        for i in range(count):
            n_dot_l[i] = n[0, i] * l[0, i] + n[1, i] * l[1, i] + n[2, i] * l[2, i]
            lit[i] = (best[i] >= 0) & (n_dot_l[i] > 0)
        if lights.shadows and counts[j] < 0:  # raykit.shadows.in_shadow, through the tree
            for i in range(count):
                if lit[i]:
                    _, blocker, _, _, _ = nearest_hit(
                        arrays, tree, stack, s[0, i], s[1, i], s[2, i], l[0, i], l[1, i],
                        l[2, i], reach[i], True,
                    )  # fmt: skip
                    lit[i] = not blocker < reach[i]
        elif lights.shadows:  # against the list: a point is dark if any opaque hit is nearer
            for m in range(counts[j]):  # than the light, whichever is nearest
                obj = candidates[j, m]
                if obj < spheres:
                    c0, c1, c2, R = centers[obj, 0], centers[obj, 1], centers[obj, 2], radii[obj]
                    for i in range(count):
                        t[i] = hit_sphere(
                            s[0, i], s[1, i], s[2, i], l[0, i], l[1, i], l[2, i], c0, c1, c2, R
                        )
                    for i in range(count):
                        lit[i] = lit[i] & ~(t[i] < reach[i])
                    continue
                board = obj - spheres  # its plane first, as hit_billboard meets it
                a0, a1, a2 = corners[board, 0], corners[board, 1], corners[board, 2]
                m0, m1, m2 = planes[board, 0], planes[board, 1], planes[board, 2]
                for i in range(count):
                    d_dot_n = l[0, i] * m0 + l[1, i] * m1 + l[2, i] * m2
                    a_minus_o_dot_n = (
                        (a0 - s[0, i]) * m0 + (a1 - s[1, i]) * m1 + (a2 - s[2, i]) * m2
                    )
                    t[i] = a_minus_o_dot_n / d_dot_n
                for i in range(count):  # hit_billboard's t where the plane's is in reach
                    if lit[i] and t[i] > 0 and t[i] < reach[i]:
                        t_hit, alpha, beta = hit_billboard(
                            s[0, i], s[1, i], s[2, i], l[0, i], l[1, i], l[2, i], arrays, board
                        )
                        if t_hit < reach[i] and billboard_color(arrays, board, alpha, beta)[3]:
                            lit[i] = False
        I0, I1, I2 = lights.colors[j, 0], lights.colors[j, 1], lights.colors[j, 2]
        for i in range(count):  # raykit.shading.lambert, where the light reaches
            sum0 = total[0, i] + k[0, i] * I0 * n_dot_l[i]
            sum1 = total[1, i] + k[1, i] * I1 * n_dot_l[i]
            sum2 = total[2, i] + k[2, i] * I2 * n_dot_l[i]
            total[0, i] = sum0 if lit[i] else total[0, i]
            total[1, i] = sum1 if lit[i] else total[1, i]
            total[2, i] = sum2 if lit[i] else total[2, i]
        for i in range(count):  # raykit.shading.blinn_phong
            hit = best[i]
            if not lit[i] or not lights.shiny[hit]:
                continue
            power = highlight(n[0, i], n[1, i], n[2, i], l[0, i], l[1, i], l[2, i], rays[3, i],
                              rays[4, i], rays[5, i], lights.shininess[hit])  # fmt: skip
            if power >= 0:
                ks = lights.specular
                total[0, i] += ks[hit, 0] * I0 * power
                total[1, i] += ks[hit, 1] * I1 * power
                total[2, i] += ks[hit, 2] * I2 * power


# ---- the loops: many rays, both cores --------------------------------------------------------


CHUNK = 256  # rays or pixels per parallel step: many per core, and one stack each
GRAINS_PER_WORKER = 16  # takes of jobs per core: few enough that taking costs nothing, and
# many enough that a core slowed by other work leaves little for the other to wait on


@intrinsic
def take(typingctx, taken, count):
    """Atomically add ``count`` to ``taken[0]`` and return its value before: the first of the
    ``count`` jobs a worker takes (numba offers no atomic add on the CPU)."""

    def codegen(context, builder, signature, args):
        counter = context.make_array(signature.args[0])(context, builder, args[0])
        return builder.atomic_rmw("add", counter.data, args[1], "monotonic")

    return types.int64(taken, types.int64), codegen


@njit(parallel=True, **_jit)
def cast_rays(arrays, tree, origins, directions, t_max):
    """:func:`nearest_hit` for each ray ``(N, 3)``: ``index (N,)``, ``t (N,)``, ``color (N, 3)``."""
    count = len(origins)
    index = np.empty(count, dtype=np.int64)
    t = np.empty(count)
    color = np.empty((count, 3))
    for chunk in prange((count + CHUNK - 1) // CHUNK):
        stack = new_stack()
        for i in range(chunk * CHUNK, min(count, (chunk + 1) * CHUNK)):
            o, d = origins[i], directions[i]
            index[i], t[i], color[i, 0], color[i, 1], color[i, 2] = nearest_hit(
                arrays, tree, stack, o[0], o[1], o[2], d[0], d[1], d[2], t_max[i]
            )
    return index, t, color


@njit(**_one_ray)
def job_pixel(down, along, points, first, top, left, across, width, xs, ys):
    """The pixel ``down`` rows and ``along`` columns into a job of :func:`trace` (``across``
    columns wide): ``(p, x, y)``, where its results go and its upper-left corner. (Rows and
    columns, not a running count: an integer division per pixel cost more than its ray.)"""
    if points:
        q = first + down * across + along
        return q, xs[q], ys[q]
    return (top + down) * width + left + along, float(left + along), float(top + down)


@njit(parallel=True, **_jit)
def trace(arrays, tiles, tree, lights, camera, width, height, jobs, workers, xs, ys, offsets,
          centre, empty, rgb, index, t):  # fmt: skip
    """The lecture's loop: for each pixel, per sample offset ``offsets (S, 2)`` in order, the
    viewing ray and its nearest hit (:func:`primary_ray`, or a packet of them:
    :func:`primary_rays`), and its colour, flat or shaded (:func:`shade_ray`), summed and
    divided by S as :class:`raykit.engine.regions.Image` takes the mean; and the object index
    and t of the ray through the pixel centre, which is sample ``centre`` (-1: cast one more
    ray there). Results go to ``rgb (P, 3)``, ``index``, ``t (P,)``. Which pixels, either way:

    * whole tiles (``xs`` empty): ``jobs (J,)`` are tile numbers (:func:`screen_tiles`), and
      their pixels are the image's, row by row (P = ``height`` x ``width``) with their upper-left
      corners at (column, row). A tile that no object's screen rectangle meets sees only the
      background: its pixels are given ``empty (3,)`` (the background's mean over the samples,
      :func:`_mean_of_samples`), index -1 and t = inf, and no ray;
    * points (``xs``, ``ys (P,)``, the upper-left corners): ``jobs`` are CHUNKs of them.

    Each job runs on one core, whole (so does a tile's list of objects): it finds all its
    viewing rays' hits first, then in a lit scene each light's :func:`shadow_lists` for the box
    they lie in, then the colours."""
    start, tiles_x, size = tiles.start, tiles.tiles_x, tiles.size
    points = len(xs)
    samples = len(offsets)
    # one worker per core (``workers``: numba.get_num_threads()), each with its own room for a
    # job's rays (making it for each job cost more than a small tile's rays), takes the next
    # grain of jobs whenever it is free: a core slowed by other work takes fewer
    grain = max(1, len(jobs) // (workers * GRAINS_PER_WORKER))
    taken = np.zeros(1, dtype=np.int64)
    for _ in prange(workers):
        n = (CHUNK if points else size * size) * (samples + 1)  # rays a job may cast
        lists = len(lights.point) if lights.shadows else 0
        room = (
            new_stack(),
            np.empty((2, n)),  # each ray's image point
            np.empty((6, n)),  # its origin and direction
            np.empty(n, dtype=np.int64),  # its hit's object index
            np.empty(n),  # t
            np.empty((3, n)),  # colour
            np.empty(n, dtype=np.bool_),  # whether the ray was made (primary_ray)
            np.empty(n, dtype=np.bool_),  # room for primary_rays
            np.empty(n),
            np.empty((2, 3)),  # the box of the surface points (shadow_lists)
            np.empty((lists, SHADOW_CANDIDATES), dtype=np.int64),
            np.full(len(lights.point), -1, dtype=np.int64),  # without lists: walk the tree
            np.empty((6, 5)),  # a shadow volume
            np.empty(HOLDING_CHUNK, dtype=np.int64),  # primary_ray's entries that hold its point
            new_lanes(n if lights.shaded else 0),  # shading in lanes
        )
        while True:
            first_job = take(taken, grain)
            if first_job >= len(jobs):
                break
            for j in range(first_job, min(len(jobs), first_job + grain)):
                if points:  # a row of points, each in whichever tile holds it
                    first = jobs[j] * CHUNK
                    rows = 1
                    across = min(CHUNK, points - first)
                    top = 0
                    left = 0
                    tile = -1
                else:
                    first = 0
                    tile = jobs[j]
                    top = (tile // tiles_x) * size
                    left = (tile % tiles_x) * size
                    rows = min(size, height - top)
                    across = min(size, width - left)
                if points or start[tile] < start[tile + 1]:
                    trace_job(arrays, tiles, tree, lights, camera, width, xs, ys, offsets,
                              centre, rgb, index, t, first, rows, top, left, across, tile,
                              room)  # fmt: skip
                    continue
                for down in range(rows):
                    for along in range(across):
                        p = (top + down) * width + left + along
                        rgb[p, 0], rgb[p, 1], rgb[p, 2] = empty[0], empty[1], empty[2]
                        index[p], t[p] = -1, np.inf


@njit(**_one_ray)
def trace_job(arrays, tiles, tree, lights, camera, width, xs, ys, offsets, centre, rgb, index, t,
              first, rows, top, left, across, tile, room):  # fmt: skip
    """One job of :func:`trace`: its ``rows`` x ``across`` pixels (:func:`job_pixel`), all in
    ``tile`` (-1: points, each in its own), with the worker's ``room`` for its rays, as
    :func:`trace` makes it. Ray i is sample i % S of the job's pixel i // S; the rays through
    the pixel centres, if cast apart (``centre`` -1), come after all those."""
    (stack, xy, rays, best, best_t, colors, made, alive, ts, box, candidates, counts, volume,
     holding, lanes) = room  # fmt: skip
    points = len(xs)
    samples = len(offsets)
    pixels = rows * across
    if not lights.shaded and (tile < 0 or not tiles.packets):
        # one ray at a time and nothing to shade: each colour goes straight into its pixel's
        # sum, and no ray is kept
        for down in range(rows):
            for along in range(across):
                p, px, py = job_pixel(down, along, points, first, top, left, across, width, xs, ys)
                r_sum, g_sum, b_sum = 0.0, 0.0, 0.0
                for sample in range(samples):
                    x, y = px + offsets[sample, 0], py + offsets[sample, 1]
                    _, hit, t_hit, r, g, b, _, _, _, _, _, _ = primary_ray(
                        arrays, tiles, camera, x, y, tile, holding
                    )
                    if sample == centre:
                        index[p], t[p] = hit, t_hit
                    r_sum += r
                    g_sum += g
                    b_sum += b
                rgb[p, 0] = r_sum / samples
                rgb[p, 1] = g_sum / samples
                rgb[p, 2] = b_sum / samples
                if centre < 0:
                    _, hit, t_hit, _, _, _, _, _, _, _, _, _ = primary_ray(
                        arrays, tiles, camera, px + 0.5, py + 0.5, tile, holding
                    )
                    index[p], t[p] = hit, t_hit
        return
    extra = 1 if centre < 0 else 0
    n = pixels * (samples + extra)
    for down in range(rows):
        for along in range(across):
            q = down * across + along
            _, px, py = job_pixel(down, along, points, first, top, left, across, width, xs, ys)
            for sample in range(samples):  # offsets in [0, 1): the point stays in its tile
                i = q * samples + sample
                xy[0, i], xy[1, i] = px + offsets[sample, 0], py + offsets[sample, 1]
            if extra:
                i = pixels * samples + q
                xy[0, i], xy[1, i] = px + 0.5, py + 0.5
    if tile >= 0 and tiles.packets:
        primary_rays(
            arrays, tiles, camera, tile, n, xy, rays, best, best_t, colors, made, alive, ts
        )
    else:
        for i in range(n):
            made[i], best[i], best_t[i], colors[0, i], colors[1, i], colors[2, i], rays[0, i], \
                rays[1, i], rays[2, i], rays[3, i], rays[4, i], rays[5, i] = primary_ray(
                    arrays, tiles, camera, xy[0, i], xy[1, i], tile, holding
                )  # fmt: skip
    if lights.shaded:  # each light for all the job's surface points at once, then mirrors
        shaded = pixels * samples
        largest = surface_lanes(arrays, lights, rays, best, best_t, colors, shaded, lanes, box)
        if lights.shadows:
            # shadow rays start off the surface by OFFSET_FACTOR x error x |n|, and |n| < 2 but
            # for a sphere smaller than its own rounding
            pad = 2.0 * OFFSET_FACTOR * largest
            shadow_lists(arrays, tree, lights, stack, box, pad, volume, candidates, counts)
        if lights.lit:
            light_lanes(arrays, tree, lights, stack, rays, best, shaded, lanes, candidates, counts)
        point, normal, error, total = lanes[0], lanes[1], lanes[2], lanes[4]
        for i in range(shaded):
            if not made[i]:
                continue
            if best[i] < 0:  # as shade_ray gives the background
                colors[0, i], colors[1, i], colors[2, i] = (
                    0.0 + 1.0 * colors[0, i],
                    0.0 + 1.0 * colors[1, i],
                    0.0 + 1.0 * colors[2, i],
                )
                continue
            colors[0, i], colors[1, i], colors[2, i] = bounce_on(
                arrays, tree, lights, stack, 0, best[i], point[0, i], point[1, i], point[2, i],
                normal[0, i], normal[1, i], normal[2, i], rays[3, i], rays[4, i], rays[5, i],
                error[i],
                0.0 + 1.0 * total[0, i], 0.0 + 1.0 * total[1, i], 0.0 + 1.0 * total[2, i],
                1.0, 1.0, 1.0,
            )  # fmt: skip
    for down in range(rows):
        for along in range(across):
            q = down * across + along
            p, _, _ = job_pixel(down, along, points, first, top, left, across, width, xs, ys)
            r_sum, g_sum, b_sum = 0.0, 0.0, 0.0
            for sample in range(samples):
                i = q * samples + sample
                r_sum += colors[0, i]
                g_sum += colors[1, i]
                b_sum += colors[2, i]
            rgb[p, 0] = r_sum / samples
            rgb[p, 1] = g_sum / samples
            rgb[p, 2] = b_sum / samples
            i = pixels * samples + q if extra else q * samples + centre
            index[p], t[p] = best[i], best_t[i]


def camera_tuple(scene: Scene) -> tuple:
    """The camera's numbers as :func:`rays_through` computes them, as plain floats (a tuple of
    numbers, not arrays, so that a loop of :func:`viewing_ray` keeps them in registers)."""
    camera = scene.camera
    u, v, w = camera.frame
    Wp, Hp = camera.plane_size
    plane = (-Wp / 2, Wp / camera.width, Hp / 2, Hp / camera.height, camera.d,
             float(camera.projection == "orthographic"))  # fmt: skip
    return tuple(float(x) for x in (*camera.eye, *u, *v, *w, *plane))


def screen_tiles(
    scene: Scene, arrays: Arrays, size: int | None = None, packets: bool | None = None
) -> Tiles:
    """The primary rays' skip: every object's screen rectangle
    (:func:`raykit.engine.screen_bounds.scene_bounds`, conservative), a lower bound on the t
    at which a viewing ray can meet it (``closest (K,)``: a sphere's distance from the eye less
    its radius, or in front of the image plane for orthographic rays, less a rounding margin; 0
    for a billboard), and each ``size`` x ``size`` tile's objects nearest first
    (:func:`bin_by_tile`), as :class:`Tiles`, whose rays go in ``packets``
    (:func:`primary_rays`) or one at a time (:func:`primary_ray`). Not given, both are
    :func:`tile_side`'s choice; a size given alone goes in packets from PACKET_SIDE up."""
    camera = scene.camera
    bounds = scene_bounds(camera, arrays.centers, arrays.radii, scene.billboards)
    if size is None:
        size, packets = tile_side(bounds, camera.width, camera.height)
    elif packets is None:
        packets = size >= PACKET_SIDE
    closest = np.zeros(scene.object_count)
    if scene.spheres:
        centers, radii = arrays.centers, arrays.radii
        eye = np.asarray(camera.eye, dtype=float)
        if camera.projection == "orthographic":
            distance = -dot(centers - eye, camera.frame[2])
        else:
            distance = length(centers - eye)
        margin = 1e-9 * (np.abs(distance) + radii + np.abs(eye).max() + np.abs(centers).max(axis=1))
        closest[: len(radii)] = np.maximum(0.0, distance - radii - margin)
    tiles_x = -(-camera.width // size)
    tiles_y = -(-camera.height // size)
    by_distance = np.argsort(closest, kind="stable")
    start, objects, entries = bin_by_tile(bounds, closest, by_distance, tiles_x, tiles_y, size)
    return Tiles(start, objects, entries, tiles_x, size, packets)


# which tiles primary rays take their objects from, and whether in packets (tile_side; timed by
# python benchmarks/engines.py --tile-sides, docs/benchmarks/tile_sides.md):
WIDE_SIDE = 16  # packets of 16 pixels a side where such tiles list on average
SPARSE_OBJECTS = 4  # this many objects or fewer;
PACKET_SIDE = 8  # else of 8 pixels a side (fewer than 64 rays fill too few vectors) where
PACKET_OBJECTS = 12  # such tiles list this many or fewer;
CROWDED_SIDE = 4  # else one ray at a time, in tiles of 4 pixels a side


def tile_side(bounds: np.ndarray, width: int, height: int) -> tuple[int, bool]:
    """``(side, packets)`` for the objects' screen rectangles ``bounds (K, 4)`` on a ``width``
    x ``height`` image. A packet (:func:`primary_rays`) tests each object of its tile against
    all its rays, 8 to a vector instruction, where one ray at a time (:func:`primary_ray`)
    tests only the objects whose rectangle holds the ray's point, with a branch each (on the
    objects, not on the entries checked for them, :func:`primary_ray`): packets win while a
    tile's list is short, and the larger the packet the fewer tiles' overheads, as
    long as the list stays short. So: WIDE_SIDE packets where those tiles list SPARSE_OBJECTS
    or fewer on average, PACKET_SIDE packets where those list PACKET_OBJECTS or fewer, and
    else one ray at a time in CROWDED_SIDE tiles. ``python benchmarks/engines.py
    --tile-sides`` times each choice (docs/benchmarks/tile_sides.md)."""
    seen = bounds[~np.isnan(bounds).any(axis=1)]

    def listed(side: int) -> float:  # objects in an average tile of this side
        across = np.floor(seen[:, 1] / side) - np.floor(seen[:, 0] / side) + 1
        down = np.floor(seen[:, 3] / side) - np.floor(seen[:, 2] / side) + 1
        return (across * down).sum() / (-(-width // side) * -(-height // side))

    if listed(WIDE_SIDE) <= SPARSE_OBJECTS:
        return WIDE_SIDE, True
    if listed(PACKET_SIDE) <= PACKET_OBJECTS:
        return PACKET_SIDE, True
    return CROWDED_SIDE, False


def caster(scene: Scene, arrays: Arrays | None = None) -> Callable[..., Hits]:
    """A :data:`raykit.shadows.Caster` over the whole scene: the nearest hits of any rays, as
    :func:`raykit.render.secondary_caster` gives them, found by :func:`cast_rays`."""
    arrays = arrays or scene_arrays(scene)
    tree = scene_tree(scene)

    def cast(origins, directions, t_max=None) -> Hits:
        t_max = np.full(len(origins), np.inf) if t_max is None else t_max
        # arrays of one kind, as _one_kind makes them: a new kind is a new compile
        origins, directions, t_max = (
            np.require(x, float, "CAW") for x in (origins, directions, t_max)
        )
        return Hits(*cast_rays(arrays, tree, origins, directions, t_max))

    return cast


class Prepared(NamedTuple):
    """A scene made ready for the kernels (:func:`prepare`): its :class:`Arrays`, screen tiles
    (:func:`screen_tiles`), BVH (:class:`Tree`, for shadow and mirror rays; empty when the
    scene has none), :class:`Lights` and camera (:func:`camera_tuple`)."""

    scene: Scene
    arrays: Arrays
    tiles: Tiles
    tree: Tree
    lights: Lights
    camera: tuple


def prepare(scene: Scene) -> Prepared:
    """Everything the kernels need of ``scene`` that does not depend on the samples: made once,
    it can be rendered many times (:func:`render`). It is what Mitsuba's ``load_dict`` does when
    it builds its BVH, and the camera's screen tiles besides (a raykit scene holds its camera)."""
    arrays = scene_arrays(scene)
    lights = scene_lights(scene)
    tree = scene_tree(scene) if lights.shaded else _NO_TREE
    return Prepared(scene, arrays, screen_tiles(scene, arrays), tree, lights, camera_tuple(scene))


def render(scene: Scene | Prepared, samples: int = 1, *, adaptive: bool = False, progress=None):
    """What :func:`raykit.render.render` renders, with the kernels above:
    ``(rgb (H, W, 3), object_index (H, W), t (H, W))``, of a scene or of a :class:`Prepared`
    one. ``progress`` is told each band of finished pixels, as the numpy engine tells it each
    tile."""
    started = time.perf_counter()
    sample_offsets(samples)  # refuses n < 1 before any work
    n = 1 if adaptive else samples  # adaptive: one ray per pixel first, as the numpy engine
    prepared = scene if isinstance(scene, Prepared) else prepare(scene)
    scene, arrays, tiles = prepared.scene, prepared.arrays, prepared.tiles
    kernels = prepared[1:]
    width, height = scene.camera.width, scene.camera.height
    offsets = sample_offsets(n)
    centre = centre_sample(n)
    empty = _mean_of_samples(arrays.background, len(offsets))
    rgb = np.empty((height * width, 3))  # first written by both cores: faster than by numpy
    index = np.empty(height * width, dtype=np.int64)
    t = np.empty(height * width)
    tiles_x, size = tiles.tiles_x, tiles.size
    tile_count = -(-height // size) * tiles_x
    # tiles per kernel call: bands of rows for a progress bar, else all at once (each call
    # starts both cores anew, and waits for the slower)
    band = max(1, ROWS_PER_CALL // size) * tiles_x if progress is not None else tile_count
    nothing = np.zeros(0)
    for first in range(0, tile_count, band):
        jobs = np.arange(first, min(first + band, tile_count))
        trace(*kernels, width, height, jobs, _workers(jobs), nothing, nothing, offsets,
              -1 if centre is None else centre, empty, rgb, index, t)  # fmt: skip
        if progress is not None:
            rows = min(height, (first + band) // tiles_x * size) - first // tiles_x * size
            progress(rows * width)
    rgb, index, t = (
        rgb.reshape(height, width, 3),
        index.reshape(height, width),
        t.reshape(height, width),
    )
    if adaptive and samples > 1:  # the numpy engine's refinement, with these colours
        edge = edge_pixels(rgb, index)
        at_the_point = np.zeros((1, 2))  # each point its own one sample

        def colors(region, x, y):
            x, y = np.asarray(x, float), np.asarray(y, float)
            out = np.empty((len(x), 3))
            jobs = np.arange(-(-len(x) // CHUNK))
            trace(*kernels, width, height, jobs, _workers(jobs), x, y, at_the_point, 0, empty, out,
                  np.empty(len(x), np.int64),
                  np.empty(len(x)))  # fmt: skip
            return out

        refine(regions(scene, skip_hidden=False), colors, rgb, edge, samples)
    _compiled_once(started)
    return rgb, index, t


def _mean_of_samples(color: np.ndarray, count: int) -> np.ndarray:
    """``color (3,)`` summed ``count`` times and divided by it, as :func:`trace` takes the mean
    of a pixel's samples (the result may differ from ``color`` in its last bit)."""
    total = np.zeros(3)
    for _ in range(count):
        total = total + color
    return total / count


def _workers(jobs: np.ndarray) -> int:
    """How many cores :func:`trace` shares ``jobs`` among (one at least)."""
    return max(1, min(numba.get_num_threads(), len(jobs)))


def _compiled_once(started: float) -> None:
    """After the first render of a fresh cache: mark it, and say how long compiling took."""
    global _FIRST_USE
    if _FIRST_USE and _CACHE is not None:
        (_CACHE / "compiled.ok").write_text(f"{time.perf_counter() - started:.1f} s\n")
    _FIRST_USE = False


__all__ = ["render", "prepare", "Prepared", "caster", "cast_rays", "scene_arrays", "screen_tiles"]

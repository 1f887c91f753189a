"""The scene as flat arrays for the kernels: repeats :mod:`raykit.engine.arrays` (the
spheres' columns), the billboards' numbers of :mod:`raykit.billboards`, the BVH of
:mod:`raykit.engine.bvh` and the materials and lights of :mod:`raykit.materials` and
:mod:`raykit.lights`, each number computed by the reference's own code, so the kernels start
from the same bits. Plain numpy: nothing here is compiled."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from raykit.engine.arrays import SceneArrays
from raykit.engine.bvh import BVH
from raykit.engine.noise import Dimensions
from raykit.lights import AreaLight, PointLight, toward_light
from raykit.rays import normalize
from raykit.scene import Scene
from raykit.shading import casts_shadows, needs_shading


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
    decoded: ``texels (T, 4)`` uint8 RGBA, turned into colour and opacity at each lookup as
    :func:`raykit.billboards.colors_and_opacity` turns them; ``texture_width``,
    ``texture_height (B,)``; the ``background (3,)``."""

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
            np.concatenate(texels) if texels else np.zeros((0, 4), np.uint8),
            np.asarray(scene.background, dtype=float),
        )
    )


def _one_kind(parts):
    """``parts`` (a NamedTuple) with every array C-contiguous, aligned and writeable, copied
    where it is not: numba compiles each kernel again for every new kind of
    array it is given, and a read-only one is another kind (a scene file's plain spheres come
    as read-only columns, :class:`raykit.spheres.SphereTable`). So every scene renders with
    the kernels the first compile made."""
    arrays = {
        name: np.require(value, requirements="CAW")
        for name, value in parts._asdict().items()
        if isinstance(value, np.ndarray)
    }
    return parts._replace(**arrays)


class Shading(NamedTuple):
    """What shading needs of a scene (:mod:`raykit.shading`), as arrays. Its switches:
    ``shaded`` (anything beyond flat colours: :func:`raykit.shading.needs_shading`), ``lit``
    (lights or ambient), ``shadows`` (:func:`raykit.shading.casts_shadows`), ``max_depth``
    (mirror bounces). Its lights (:mod:`raykit.lights`): per light ``point_light (L,)``
    (False: directional), ``light_vectors (L, 3)`` (a point light's position, or a directional
    light's l, made by :func:`raykit.lights.toward_light`) and intensity ``light_colors (L,
    3)``; and ``ambient (3,)``. Its materials, per object (K): the material table's columns
    (:class:`raykit.materials.MaterialTable`: ``diffuse``, ``has_diffuse``, ``specular``,
    ``shininess``, ``mirror``) and whether each ``is_shiny`` or ``is_mirror (K,)``. And the
    billboards' unit normals ``board_normals (B, 3)``, which shading uses and hitting does
    not. Stage 5: an area light is a point light whose position each ray samples
    (:func:`raykit.engine.compiled.lights.sampled`): its ``light_vectors`` row is its corner,
    ``light_edges (L, 6)`` its edges a and b, ``area (L,)`` which area light it is (-1: none),
    and ``light_dims (max_depth + 1, A)`` where each area light's uniform numbers lie at each
    mirror depth (:meth:`raykit.engine.noise.Dimensions.light`), and whether each light is a
    physically based one, ``physical (L,)``, with its area ``light_area (L,)`` and unit normal
    ``light_normals (L, 3)`` (:attr:`raykit.lights.AreaLight.frame`,
    :func:`raykit.lights.area_intensity`); each object's ``glossiness
    (K,)``, and where the glossy perturbation of the mirror bounce at each depth lies,
    ``gloss_dims (max_depth,)`` (:meth:`raykit.engine.noise.Dimensions.gloss`; empty in a scene
    whose samples take none: its mirrors reflect as ideal ones)."""

    shaded: bool
    lit: bool
    shadows: bool
    max_depth: int
    point_light: np.ndarray
    light_vectors: np.ndarray
    light_colors: np.ndarray
    ambient: np.ndarray
    diffuse: np.ndarray
    has_diffuse: np.ndarray
    specular: np.ndarray
    shininess: np.ndarray
    mirror: np.ndarray
    is_shiny: np.ndarray
    is_mirror: np.ndarray
    board_normals: np.ndarray
    area: np.ndarray
    light_edges: np.ndarray
    light_dims: np.ndarray
    glossiness: np.ndarray
    gloss_dims: np.ndarray
    physical: np.ndarray
    light_area: np.ndarray
    light_normals: np.ndarray


class CompiledScene(NamedTuple):
    """What a ray of a shaded scene may meet and read, as one argument of the kernels that shade:
    its objects (:class:`Arrays`), the BVH its shadow and mirror rays walk (:class:`Tree`), and
    its lights and materials (:class:`Shading`)."""

    arrays: Arrays
    tree: Tree
    shading: Shading


def scene_shading(scene: Scene) -> Shading:
    """The scene's :class:`Shading`, from the reference's own functions and tables."""
    table = scene.materials
    lights = scene.lights
    point = np.array([isinstance(light, PointLight | AreaLight) for light in lights], np.bool_)
    origin = np.zeros((1, 3))
    vectors = [
        np.asarray(light.position, float) if isinstance(light, PointLight)
        else np.asarray(light.corner, float) if isinstance(light, AreaLight)
        else toward_light(light, origin)[0][0]
        for light in lights
    ]  # fmt: skip
    area, areas = [], 0  # which area light each is, in the order of scene.lights (-1: none)
    for light in lights:
        area.append(areas if isinstance(light, AreaLight) else -1)
        areas += isinstance(light, AreaLight)
    edges = [
        np.concatenate([light.edge1, light.edge2]).astype(float) if isinstance(light, AreaLight)
        else np.zeros(6)
        for light in lights
    ]  # fmt: skip
    physical = [isinstance(light, AreaLight) and light.physical for light in lights]
    frames = [
        light.frame if isinstance(light, AreaLight) else (0.0, np.zeros(3)) for light in lights
    ]
    dimensions = Dimensions.of(scene)
    dims = [[dimensions.light(depth, a) for a in range(scene.area_lights)]
            for depth in range(scene.max_depth + 1)]  # fmt: skip
    gloss = [dimensions.gloss(depth) for depth in range(scene.max_depth)]
    return _one_kind(
        Shading(
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
            np.array(area, dtype=np.int64),
            np.array(edges, dtype=float).reshape(-1, 6),
            np.array(dims, dtype=np.int64).reshape(scene.max_depth + 1, scene.area_lights),
            table.glossiness.astype(float),
            np.array(gloss if dimensions.glossy else [], dtype=np.int64),
            np.array(physical, dtype=np.bool_),
            np.array([area for area, _ in frames], dtype=float),
            np.array([normal for _, normal in frames], dtype=float).reshape(-1, 3),
        )
    )


_NO_TREE = Tree(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 2), np.int64),
                *[np.zeros(0, np.int64)] * 3, np.zeros((0, 3)), np.zeros((0, 3)))  # fmt: skip


class Motion(NamedTuple):
    """A scene's moving spheres (motion blur, :mod:`raykit.sampling`) as :func:`trace_sampled
    <raykit.engine.compiled.render.trace_sampled>` moves them: ``moving``, whether any does
    (:attr:`raykit.scene.Scene.moving`); the spheres' ``velocities (S, 3)`` and ``moves (S,)``,
    whether each has a velocity (:func:`raykit.render.cast` moves only those); the shutter's
    ``shutter_open`` and ``shutter_close``; and ``time``, the dimension of a sample's uniform
    numbers that gives its ray's time (:class:`raykit.engine.noise.Dimensions`), -1 where every
    ray is at the opening (the shutter open no while, or nothing moving)."""

    moving: bool
    velocities: np.ndarray
    moves: np.ndarray
    shutter_open: float
    shutter_close: float
    time: int


def scene_motion(scene: Scene) -> Motion:
    """The scene's :class:`Motion` (nothing moving, for a scene without a shutter)."""
    spheres = len(scene.spheres)
    if not scene.moving:
        return Motion(False, np.zeros((spheres, 3)), np.zeros(spheres, dtype=np.bool_), 0.0, 0.0,
                      -1)  # fmt: skip
    velocities = np.require(scene.velocities[:spheres], float, "CAW").reshape(spheres, 3)
    shutter_open, shutter_close = (float(T) for T in scene.sampling.shutter)
    time = Dimensions.of(scene).time if scene.blurred else -1
    return Motion(True, velocities, velocities.any(axis=1), shutter_open, shutter_close, time)


def every_object_tree(scene: Scene) -> Tree:
    """A tree of one leaf, all of space its box, holding every object in index order: what the
    walk of :func:`~raykit.engine.compiled.bvh.nearest_hit` makes a test of every object, as
    :func:`raykit.render.cast` tests them in a scene whose spheres move (a box of a sphere as it
    stands does not bound where a ray at another time finds it; the reference builds none)."""
    objects = scene.object_count
    everywhere = np.full((1, 3), np.inf)
    return Tree(-everywhere, everywhere.copy(), np.full((1, 2), -1, np.int64),
                np.zeros(1, np.int64), np.full(1, objects, np.int64),
                np.arange(objects, dtype=np.int64), np.full((objects, 3), -np.inf),
                np.full((objects, 3), np.inf))  # fmt: skip


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

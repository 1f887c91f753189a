"""The compiled engine: the renderer's loop as machine code (numba), ray by ray or in packets.

One module per job, each named for the reference module it repeats: :mod:`.scene` (the scene as
arrays), :mod:`.rays`, :mod:`.spheres`, :mod:`.billboards`, :mod:`.camera`, :mod:`.hits`,
:mod:`.bvh` (the tree walk), :mod:`.surfaces`, :mod:`.lights`, :mod:`.shadows` (and the shadow
lists), :mod:`.shading` (per ray and in lanes), :mod:`.mirrors`, :mod:`.sampling` and
:mod:`.noise` (stage 5's sample patterns and uniform numbers), :mod:`.tiles` (screen tiles and
packets) and :mod:`.render` (the renderer's loop, :mod:`raykit.render` repeated, as jobs,
:mod:`.jobs`, that workers take on the threads of :mod:`.pool`); :mod:`.compiling` is the
machinery.

Install with ``pip install "raykit[fast]"``; :func:`raykit.render.render` takes it with
``engine="compiled"``, or by itself for large renders (``engine="auto"``,
:mod:`raykit.engine.choice`). Without numba nothing imports this package.

What it repeats, and how it is held to it. The lecture's numpy functions are the reference. Each
kernel below names the function it repeats and does *the same float64 operations in the same
order* on one ray, so its answers agree with the reference bit for bit, but for one pow (below).
Which function each kernel repeats is data, the twin table (:mod:`.twins`), from which come a
differential test per pair (``tests/compiled/test_<module>.py``, beside 10^5-ray checks, the
stability cases, and the PNG bytes of every example scene), the cache's key, and the line in
each reference function's documentation that names its twin. Dot products are
summed left to right with no fused multiply-add, as :func:`raykit.rays.dot` sums them (numba,
like numpy, contracts a·b + c into an FMA only under fastmath, which is off).

What it skips. Primary rays: the image is cut into square tiles (their side chosen by
:func:`.tiles.tile_side`, smaller in a crowded picture), and each tile keeps the objects whose
screen rectangle (:mod:`raykit.engine.screen_bounds`) meets it, nearest first
(:func:`.tiles.screen_tiles`). A tile no object is seen in gets the background and no ray; elsewhere
a viewing ray tests only the objects whose rectangle holds its image point, and stops at the first
that cannot come nearer than the hit it has: one ray at a time in a crowded picture, else a whole
tile's rays at once, in vectors, with masks for what each ray would skip
(:func:`.tiles.primary_rays`). Shadow rays
from what a tile sees test only the objects that may lie between it and each light: the tile's
viewing rays are all traced first, then each light's volume of shadow rays from the box of their
surface points picks its candidates from the scene (:func:`.shadows.shadow_lists`; with too
many, the rays walk the tree). Other shadow rays and mirror rays walk a bounding volume
hierarchy (the tree of :mod:`raykit.engine.bvh`, built by the same code), nearer child first,
leaving every box that starts beyond the nearest hit found, or in a scene of a few objects test
each (:data:`.bvh.DIRECT_HITS`); a shadow ray stops at its first blocker. Either way a tie keeps
the lower object index, whatever order objects come in, and a cut-out texel is no hit: the
answer is :func:`raykit.render.cast`'s. All of it is made once per scene by :func:`prepare`,
which a caller may keep and render many times with :func:`.render.render` (named as the
reference names its loop, :func:`raykit.render.render`; the package binds no ``render`` of its
own, which would hide the module of that name).

Lit scenes. :func:`.shading.shade` and :func:`.shading.surface_color` repeat
:mod:`raykit.shading` for one ray: ambient, Lambert and Blinn-Phong per light, shadow rays
(:mod:`raykit.shadows`, through the BVH) and mirror bounces (:mod:`raykit.mirrors`), with the
surface points and offsets of :mod:`raykit.surfaces`. A job's viewing rays are shaded together,
light by light, in lanes (:func:`.shading.surface_lanes`, :func:`.shading.light_lanes`): each
ray's operations in the same order, the steps that every ray takes in vector instructions, and
the shadow rays against the tile's lists; a mirror's rays then go on one at a time
(:func:`.shading.mirror_rays`, :func:`.shading.bounce_on`), compiled only for a scene with
mirrors. One operation differs: the highlight's power is the C library's pow here and numpy's
vectorised power in the reference, which disagree by one unit in the last place on a few per
cent of points; with the reference given the same pow, the two engines agree
bit for bit, and as they stand, within 4 units in the last place and to the PNG byte (tests).

Distributed scenes (stage 5). A scene with area lights, a thin lens, glossy mirrors or many samples
per pixel renders in a loop of its own (:func:`.render.trace_sampled`): each job a few pixels, each
pixel all its samples in order; through a pinhole, a batch's viewing rays tested against the objects
its pixels' screen tiles list (:func:`.tiles.row_objects`), every other ray (viewing, shadow,
mirror) against every object or through the tree. A sample's uniform numbers are
:mod:`raykit.engine.noise`'s, hashed from (seed, pixel, sample, dimension) in wrapping uint64
arithmetic (:mod:`.noise`; the Sobol' points and their scrambling too), so no number depends on
which worker takes which pixel; the sample patterns (:mod:`.sampling`), an area light's point
(:func:`.lights.sampled`), the thin lens's rays (:func:`.camera.thin_lens_rays`) and a glossy
mirror's ray (:func:`.mirrors.glossy_reflect`) repeat the reference's operations in its order.
Motion blur: each sample's ray has its own time in the shutter interval
(:func:`.sampling.shutter_times`), and each worker moves its copy of the sphere centres there
(:func:`.spheres.center_at`, :func:`.render.spheres_at`) before the ray, its shadow and mirror rays
and its normals read them; the tree is then one leaf of every object
(:func:`.scene.every_object_tree`), as the reference tests every object of a scene that moves. Such
a scene renders by an entry point of its own (:func:`.render.trace_moving`), and a still scene's
compiles its mirror rays only where it has mirrors, so that no scene compiles the kernels of another
kind. One corner differs: the reference takes a still sphere's normal from c + T·0, which turns a
centre coordinate of -0.0 into +0.0 where its hit test keeps -0.0; the engine keeps c for both, so a
normal's component can differ in the sign of a zero where a hit point's coordinate is exactly -0.0
too.

Compiling. Each kernel is compiled on first use, with the kernels it calls, and cached on disk,
kernel by kernel, in a folder keyed on the sources they are made from (the reference modules
of :mod:`.twins` included): a flat scene compiles only what
flat scenes use, a progress line shows it, and Ctrl-C leaves a usable cache (:mod:`.compiling`;
how long it takes: docs/benchmarks/compile_time.md, written by ``python
benchmarks/compile_time.py``). Only float64 is compiled.
"""

from __future__ import annotations

from raykit.engine.compiled.billboards import billboard_color_at, hit_billboard
from raykit.engine.compiled.bvh import DIRECT_HITS, nearest_hit, new_stack
from raykit.engine.compiled.camera import (
    CameraNumbers,
    camera_tuple,
    lens_tuple,
    rays_through,
    thin_lens_rays,
)
from raykit.engine.compiled.compiling import KERNEL
from raykit.engine.compiled.hits import NearestHit, keep_nearer
from raykit.engine.compiled.jobs import (
    CHUNK,
    Film,
    RayRoom,
    SampleRoom,
    ShadingRoom,
    Work,
    flat_rooms,
    grain_taken,
    lit_rooms,
    moving_rooms,
    sampled_rooms,
    take,
)
from raykit.engine.compiled.mirrors import reflect
from raykit.engine.compiled.noise import Noise, scene_noise
from raykit.engine.compiled.rays import Ray
from raykit.engine.compiled.render import (
    Prepared,
    cast_rays,
    caster,
    prepare,
    trace_flat,
    trace_lit,
    trace_moving,
    trace_sampled,
)
from raykit.engine.compiled.scene import (
    Arrays,
    CompiledScene,
    Shading,
    Tree,
    scene_arrays,
    scene_shading,
    scene_tree,
)
from raykit.engine.compiled.shading import (
    Lanes,
    blinn_phong,
    bounce_on,
    lambert,
    light_lanes,
    mirror_rays,
    new_lanes,
    shade,
    surface_color,
    surface_lanes,
)
from raykit.engine.compiled.shadows import DIRECT_LISTS, SHADOW_CANDIDATES, shadow_lists
from raykit.engine.compiled.spheres import hit_sphere
from raykit.engine.compiled.surfaces import start, surface_points
from raykit.engine.compiled.tiles import (
    CROWDED_SIDE,
    DENSE_SIDE,
    HOLDING_CHUNK,
    PACKET_SIDE,
    WIDE_SIDE,
    Tiles,
    primary_ray,
    primary_rays,
    screen_tiles,
    tile_side,
)
from raykit.surfaces import OFFSET_FACTOR

__all__ = [
    "CHUNK", "CROWDED_SIDE", "CameraNumbers", "DENSE_SIDE", "DIRECT_HITS", "DIRECT_LISTS",
    "HOLDING_CHUNK",
    "CompiledScene", "Film", "KERNEL", "OFFSET_FACTOR", "PACKET_SIDE", "SHADOW_CANDIDATES",
    "WIDE_SIDE", "Arrays", "Lanes", "NearestHit", "Noise", "Prepared", "Ray", "RayRoom",
    "SampleRoom", "Shading", "ShadingRoom", "Tiles", "Tree", "Work", "billboard_color_at",
    "blinn_phong", "bounce_on", "camera_tuple", "cast_rays", "caster", "flat_rooms",
    "grain_taken", "hit_billboard", "hit_sphere", "keep_nearer", "lambert", "lens_tuple",
    "light_lanes", "lit_rooms", "mirror_rays", "moving_rooms", "nearest_hit", "new_lanes",
    "new_stack", "prepare", "primary_ray", "primary_rays", "rays_through", "reflect",
    "sampled_rooms", "scene_arrays", "scene_noise", "scene_shading", "scene_tree",
    "screen_tiles", "shade", "shadow_lists", "start", "surface_color", "surface_lanes",
    "surface_points", "take", "thin_lens_rays", "tile_side", "trace_flat", "trace_lit",
    "trace_moving", "trace_sampled",
]  # fmt: skip

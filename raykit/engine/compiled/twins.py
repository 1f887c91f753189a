"""The twin table: which reference function each compiled kernel repeats, in one place.

Each row of :data:`TWINS` pairs a kernel (its module under :mod:`raykit.engine.compiled` and
its name) with the reference function it repeats (module and name, a method as
``Class.method``), and says why where the kernel's name is not the reference's. :data:`OWN`
lists the kernels that repeat no reference function (the compiled engine's own machinery: its
skips, its jobs, its rooms), each with why; :data:`WITHIN`, the reference functions a kernel
repeats inside itself, and :data:`EVERYWHERE`, those every kernel writes out. Every kernel is in
:data:`TWINS` or :data:`OWN`, and each function of the lecture's modules that the numpy engine
runs is a twin's reference, in :data:`WITHIN` or :data:`EVERYWHERE`, or run by the compiled
engine itself, as it prepares a scene (tests/compiled/test_twins.py).

What reads the table:

* the differential tests, one per row (tests/compiled/test_twins.py);
* the cache folder's key (:func:`raykit.engine.choice.cache_folder`), which hashes the sources
  of the reference modules named here beside the kernels' own, so that an edit of a reference
  function or constant makes a new folder;
* the documentation's build (docs/conf.py), which adds to each reference function's entry the
  line naming its twin; the sources, and so the student release, never hold that line.

Plain data, importing nothing: :mod:`raykit.engine.choice` reads it without importing numba
(:func:`raykit.engine.choice.twin_table`).
"""

from __future__ import annotations

from typing import NamedTuple


class Twin(NamedTuple):
    """Kernel ``module.name`` (under raykit.engine.compiled) repeats ``reference`` (a function's
    full dotted name); ``why`` says why its name differs, empty where it is the same."""

    kernel: str
    reference: str
    why: str = ""


TWINS = (
    Twin("rays.nearest_positive", "raykit.rays.nearest_positive"),
    Twin("spheres.hit_sphere", "raykit.spheres.hit_sphere"),
    Twin("spheres.center_at", "raykit.spheres.center_at"),
    Twin("billboards.hit_billboard", "raykit.billboards.hit_billboard"),
    Twin("billboards.billboard_color_at", "raykit.billboards.billboard_color_at"),
    Twin("camera.rays_through", "raykit.camera.rays_through"),
    Twin("hits.keep_nearer", "raykit.hits.Hits.keep_nearer"),
    Twin(
        "lights.toward_point_light",
        "raykit.lights.toward_light",
        "a point light's only: a directional light's l is its direction, read where it is used",
    ),
    Twin("lights.sampled", "raykit.lights.sampled"),
    Twin("lights.area_intensity", "raykit.lights.area_intensity"),
    Twin(
        "lights.area_light",
        "raykit.lights.area_intensity",
        "the light's numbers it reads (its AreaLight), read once before a loop over points",
    ),
    Twin("camera.thin_lens_rays", "raykit.camera.thin_lens_rays"),
    Twin("noise.mix64", "raykit.engine.noise.mix64"),
    Twin("noise.counter_hash", "raykit.engine.noise.counter_hash"),
    Twin(
        "noise.pixel_hash",
        "raykit.engine.noise.counter_hash",
        "its first two parts, (seed, pixel), the start every counter of a pixel shares",
    ),
    Twin(
        "noise.hash_on",
        "raykit.engine.noise.counter_hash",
        "its last two parts, (sample, dimension), folded into the pixel's hash",
    ),
    Twin(
        "noise.fold",
        "raykit.engine.noise.counter_hash",
        "one of its steps: one part of the counter folded into the hash so far",
    ),
    Twin("noise.uniforms", "raykit.engine.noise.uniforms"),
    Twin("noise.uniform", "raykit.engine.noise.uniforms", "from a counter's hash made before"),
    Twin("noise.shuffle", "raykit.engine.noise.shuffle"),
    Twin(
        "noise.round_keys",
        "raykit.engine.noise.shuffle",
        "its four rounds' keys, which a pixel's samples share",
    ),
    Twin(
        "noise.shuffle_by",
        "raykit.engine.noise.shuffle",
        "its rounds, their keys made before (round_keys)",
    ),
    Twin(
        "noise.shuffle_shape",
        "raykit.engine.noise.shuffle",
        "the mask and shift of its rounds, from the count",
    ),
    Twin(
        "noise.shuffle_rounds",
        "raykit.engine.noise.shuffle",
        "its four rounds on one value, which shuffle_by walks and shuffle_of_power takes once",
    ),
    Twin(
        "noise.pixel_keys",
        "raykit.engine.noise.PixelSamples.of",
        "what its numbers of one pixel take from the pixel alone, made once for all its samples",
    ),
    Twin(
        "noise.sample_numbers",
        "raykit.engine.noise.PixelSamples.of",
        "sample k of one pixel, from its pixel_keys, into a row of numbers, by each sampler (the"
        " Sobol' table as data), only the dimensions the scene reads",
    ),
    Twin(
        "noise.shuffle_of_power",
        "raykit.engine.noise.shuffle",
        "the shuffle of a power-of-two count (the Sobol' sampler's), its rounds once, with no loop",
    ),
    Twin(
        "noise.sobol_numbers",
        "raykit.engine.noise.PixelSamples.of",
        "sample_numbers of the Sobol' sampler for a batch of samples of several pixels, a"
        " dimension at a time for all of them, in 32-bit integers",
    ),
    Twin("sampling.point_in_pixel", "raykit.sampling.point_in_pixel"),
    Twin("sampling.jittered_point", "raykit.sampling.jittered_point"),
    Twin("sampling.point_on_parallelogram", "raykit.sampling.point_on_parallelogram"),
    Twin("sampling.point_on_disk", "raykit.sampling.point_on_disk"),
    Twin(
        "sampling.cos_sin",
        "raykit.sampling._cos_sin",
        "the reference's name is private to its module",
    ),
    Twin("sampling.point_on_lens", "raykit.sampling.point_on_lens"),
    Twin("sampling.basis_around", "raykit.sampling.basis_around"),
    Twin("sampling.perturbed_direction", "raykit.sampling.perturbed_direction"),
    Twin("sampling.shutter_times", "raykit.sampling.shutter_times"),
    Twin("sampling.reverse_bits", "raykit.sampling.reverse_bits"),
    Twin(
        "sampling.unit_number",
        "raykit.sampling.sobol_set",
        "a point's 32-bit integer times 2^-32, exactly, by a conversion AVX2 makes for vectors",
    ),
    Twin("sampling.sobol_points", "raykit.sampling.sobol_points"),
    Twin("sampling.owen_scramble", "raykit.sampling.owen_scramble"),
    Twin(
        "sampling.owen_hash",
        "raykit.sampling.owen_scramble",
        "its hash alone, on a value whose bits are mirrored already (a Sobol' point's first"
        " dimension is its index mirrored)",
    ),
    Twin("surfaces.surface_points", "raykit.surfaces.surface_points"),
    Twin(
        "surfaces.point_and_normal",
        "raykit.surfaces.surface_points",
        "its object's numbers given (hit_object), with no branch: the step of surface_lanes's"
        " vector loop",
    ),
    Twin("surfaces.start", "raykit.surfaces.SurfacePoints.start"),
    Twin(
        "shadows.point_light_reach",
        "raykit.shadows.light_reach",
        "a point light's only: a directional light's reach is inf, set where it is used",
    ),
    Twin("shading.lambert", "raykit.shading.lambert"),
    Twin("shading.blinn_phong", "raykit.shading.blinn_phong"),
    Twin("shading.surface_color", "raykit.shading.surface_color"),
    Twin(
        "shading.surface_lanes",
        "raykit.shading.surface_color",
        "its first part (point, k, ambient) for a job's rays side by side, in lanes",
    ),
    Twin(
        "shading.light_lanes",
        "raykit.shading.surface_color",
        "its lights' part (Lambert, shadow, highlight) for a job's rays side by side, in lanes",
    ),
    Twin("mirrors.reflect", "raykit.mirrors.reflect"),
    Twin("mirrors.glossy_reflect", "raykit.mirrors.glossy_reflect"),
    Twin("shading.shade", "raykit.shading.shade"),
    Twin(
        "shading.bounce_on",
        "raykit.shading.shade",
        "shade's loop over mirror bounces, after the first surface",
    ),
    Twin(
        "shading.mirror_rays",
        "raykit.shading.shade",
        "shade's mirror bounces for a job's rays, once their first surface is shaded in lanes",
    ),
    Twin(
        "bvh.nearest_hit",
        "raykit.render.cast",
        "cast for one ray through the tree (raykit.engine.bvh), as BVH.cast answers it",
    ),
    Twin(
        "bvh.enters",
        "raykit.engine.bvh._enters",
        "the reference's name is private to its module",
    ),
    Twin("render.cast_rays", "raykit.render.cast", "cast for many rays in parallel, by the tree"),
    Twin(
        "tiles.primary_ray",
        "raykit.render.cast",
        "cast for one viewing ray, of its screen tile's objects only (raykit.engine.tiles)",
    ),
    Twin(
        "tiles.primary_rays",
        "raykit.render.cast",
        "cast for a packet of a tile's viewing rays, in lanes",
    ),
    Twin(
        "tiles.lane_offer",
        "raykit.hits.Hits.keep_nearer",
        "keep_nearer's rule for one lane of a packet, its hit of the object given",
    ),
    Twin(
        "tiles.bin_by_tile",
        "raykit.engine.tiles.regions",
        "each tile's objects as one list, nearest first, for a ray to read straight through",
    ),
    Twin(
        "tiles.row_objects",
        "raykit.engine.tiles.regions",
        "the objects a row of pixels' screen tiles list, for a pinhole's distributed samples",
    ),
    Twin("render.trace_flat", "raykit.render.render", "render's loop for a flat scene"),
    Twin("render.trace_lit", "raykit.render.render", "render's loop for a shaded scene"),
    Twin("render.flat_job", "raykit.render.render", "render's loop over one job's pixels, flat"),
    Twin("render.lit_job", "raykit.render.render", "render's loop over one job's pixels, shaded"),
    Twin(
        "render.trace_sampled",
        "raykit.render.render",
        "render's loop for a distributed scene (stage 5) whose spheres stand still",
    ),
    Twin(
        "render.trace_moving",
        "raykit.render.render",
        "render's loop for a distributed scene whose spheres move (motion blur)",
    ),
    Twin(
        "render.sampled_job",
        "raykit.render.render",
        "render's loop over one job's pixels, distributed, each with all its samples",
    ),
    Twin(
        "render.sampled_lanes",
        "raykit.render.render",
        "render's loop over one job's pixels, distributed, where nothing moves: their samples in "
        "lanes",
    ),
    Twin(
        "render.cast_each",
        "raykit.render.cast",
        "cast's nearest hits of a batch of rays, each through the tree",
    ),
    Twin(
        "render.cast_batch",
        "raykit.render.cast",
        "cast's nearest hits of a batch of viewing rays, of the objects their pixels may show",
    ),
    Twin(
        "render.cast_lanes",
        "raykit.render.cast",
        "cast's nearest hits of a batch of viewing rays, each object for all at once",
    ),
    Twin(
        "render.spheres_at",
        "raykit.render.cast",
        "cast's centres of the spheres at one ray's time, a moving one's by center_at",
    ),
    Twin(
        "jobs.pixel_means",
        "raykit.engine.regions.Image.mean",
        "the mean of each pixel's samples, as the image takes it, for one job",
    ),
)

# kernels that repeat no reference function, and why
OWN = {
    "bvh.new_stack": "room for a tree walk, reused from ray to ray",
    "shading.new_lanes": "room for shading a job's rays in lanes",
    "jobs.new_ray_room": "room for a job's rays",
    "jobs.new_shading_room": "room for shading a job's rays",
    "jobs.new_sample_room": "room for a distributed render's samples' uniform numbers",
    "jobs.take": "an atomic add: how workers take jobs",
    "jobs.grain_taken": "the jobs a worker takes next: the workers' loop",
    "jobs.job_of": "a job's pixels: the workers' own cut of the image",
    "jobs.job_pixel": "a pixel of a job",
    "jobs.job_points": "a job's image points",
    "jobs.keeps_hits": "whether a render keeps each pixel's object index and t",
    "jobs.centre_rays": "whether a job casts a ray of its own through each pixel centre",
    "jobs.background_job": "a tile no object is seen in: the background, with no ray",
    "render.every_object": "a distributed render's shadow lists: every object, as the reference",
    "surfaces.hit_object": "what a hit's surface point reads of its object, read one ray at a time",
    "tiles.lanes_under": "the lanes of a packet an object's screen rectangle can hold",
    "tiles.farthest_hit": "where a packet stops: the farthest of its lanes' hits",
    "tiles.take_nearer": "a packet's lanes take the hits lane_offer chose, an array at a time",
    "mirrors.sign": "np.sign of one number, which glossy_reflect's reference compares",
    "shadows.extent": "the shadow lists' cull (the reference tests every object)",
    "shadows.box_extent": "the shadow lists' cull",
    "shadows.box_apart": "the shadow lists' cull",
    "shadows.sphere_apart": "the shadow lists' cull",
    "shadows.shadow_volume": "the shadow lists' cull",
    "shadows.candidate": "the shadow lists' cull",
    "shadows.shadow_candidates": "the shadow lists' cull",
    "shadows.shadow_lists": "the shadow lists' cull",
}


# reference functions that a kernel repeats inside itself, not as a kernel of its own: the
# reference function, and the kernel that holds its copy
WITHIN = {
    "raykit.spheres.sphere_roots": "spheres.hit_sphere",
    "raykit.spheres.sphere_normals": "surfaces.surface_points",
    "raykit.planes.hit_plane": "billboards.hit_billboard",
    "raykit.planes.hit_points_on_plane": "billboards.hit_billboard",
    "raykit.billboards.texel_indices": "billboards.billboard_color_at",
    "raykit.billboards.colors_and_opacity": "billboards.billboard_color_at",
    "raykit.billboards.billboard_normals": "surfaces.surface_points",
    "raykit.camera._in_plane": "camera.rays_through",
    "raykit.camera.region_points": "jobs.job_points",
    "raykit.hits.Hits.none": "bvh.nearest_hit",
    "raykit.hits.solid": "hits.keep_nearer",
    "raykit.rays.point_at": "surfaces.surface_points",
    "raykit.shadows.in_shadow": "shading.surface_color",
    "raykit.render.illumination": "render.lit_job",
    "raykit.sampling.sobol_set": "noise.sample_numbers",
    "raykit.shading._rows": "shading.surface_color",
}

# reference functions every kernel writes out where it needs them, and why no kernel of their own
EVERYWHERE = {
    "raykit.rays.dot": "a0 * b0 + a1 * b1 + a2 * b2, left to right, as it sums: no kernel to call",
    "raykit.rays.length": "math.sqrt of the dot product, written out",
    "raykit.rays.normalize": "each component over the length, written out",
    "raykit.surfaces.SurfacePoints.take": "rows of N points; a kernel holds one point",
}


def twins_of(reference: str) -> list[Twin]:
    """The rows of :data:`TWINS` that repeat ``reference`` (a full dotted name)."""
    return [twin for twin in TWINS if twin.reference == reference]


def doc_lines(reference: str) -> list[str]:
    """The lines the documentation's build adds to ``reference``'s entry (docs/conf.py): its
    compiled twins, each with its test file and why its name differs, or the kernel it is
    repeated in. Empty for a function with none."""
    lines = []
    for twin in twins_of(reference):
        module, name = twin.kernel.split(".")
        why = f" ({twin.why})" if twin.why else ""
        lines.append(
            f"Compiled twin: :func:`raykit.engine.compiled.{module}.{name}`{why}; tested by "
            f"``tests/compiled/test_{module}.py``."
        )
    if reference in WITHIN:
        module, name = WITHIN[reference].split(".")
        lines.append(
            f"Compiled twin: repeated inside :func:`raykit.engine.compiled.{module}.{name}`; "
            f"tested by ``tests/compiled/test_{module}.py``."
        )
    return lines


def reference_modules() -> list[str]:
    """The modules whose functions the kernels repeat (:data:`TWINS`, :data:`WITHIN`), each
    once, in the table's order."""
    modules: list[str] = []
    for reference in [twin.reference for twin in TWINS] + list(WITHIN):
        module = reference.rpartition(".")[0]
        while module.rpartition(".")[2][:1].isupper():  # a method: Class.method
            module = module.rpartition(".")[0]
        if module not in modules:
            modules.append(module)
    return modules

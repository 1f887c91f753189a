"""The renderer's loop (raykit.engine.compiled.render) against raykit.render.render: whole renders
to the PNG byte, whoever takes which job, the arguments' kinds and types."""

from __future__ import annotations

import contextlib
import inspect
import json
from dataclasses import replace

import numba
import numpy as np
import pytest

from conftest import SCENES, shifted_scene
from raykit.engine import compiled
from raykit.engine.choice import compiled_refuses
from raykit.io.scene_json import load_scene, scene_from_dict
from raykit.lights import AreaLight
from raykit.render import render
from raykit.sampling import SAMPLERS, Sampling

from .harness import (
    caster_answers_what_cast_answers,
    crowd,
    distributed_scene,
    exactly,
    packet_scenes,
    run_python,
    same_render,
    small_render,
    twin_test,
    two_threads,
)

EXAMPLES = sorted(SCENES.glob("*.json"))  # motion_blur.json among them


def test_prepare_decodes_on_other_threads_only_the_large_textures_the_cache_lacks(
    tmp_path, monkeypatch
):
    # a cached decode's read and a small decode are Python's work, which other threads only slow
    from PIL import Image

    from raykit.io.textures import CACHED_FROM

    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    side = int(CACHED_FROM**0.5)
    rng = np.random.default_rng(7)
    for name, size in (("small", 8), ("cached", side), ("new", side)):
        rgba = rng.integers(0, 256, (size, size, 4), dtype=np.uint8)
        Image.fromarray(rgba, "RGBA").save(tmp_path / f"{name}.png")
    data = json.loads((SCENES / "classic.json").read_text())
    for board, name in zip(data["billboards"], ("small", "cached", "new", "cached"), strict=False):
        board["image"] = f"{name}.png"
    load_scene_with = lambda: scene_from_dict(data, "scene.json", tmp_path)  # noqa: E731
    load_scene_with().billboards[1].texture.rgba  # noqa: B018 (decoded once: now cached)
    handed = []
    each_at_once = compiled.render.each_at_once
    monkeypatch.setattr(
        compiled.render,
        "each_at_once",
        lambda function, items, threads: (
            handed.append([t.path.name for t in items]) or each_at_once(function, items, threads)
        ),
    )
    scene = load_scene_with()
    prepared = compiled.prepare(scene)
    assert handed == [["new.png"]]
    assert all(board.texture.decoded for board in scene.billboards)
    again = compiled.prepare(load_scene_with())
    assert handed == [["new.png"], []]  # both large ones are cached now
    assert np.array_equal(prepared.arrays.texels, again.arrays.texels)


def test_the_renderers_loop_is_a_module_as_the_reference_is():
    import raykit.engine.compiled.render as loop  # the module, not a function of its name

    assert inspect.ismodule(loop) and loop is compiled.render
    assert loop.render.__module__ == "raykit.engine.compiled.render"


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_every_example_scene_gives_the_same_png_bytes_with_both_engines(path):
    scene = load_scene(path)  # soft_shadows, depth_of_field, glossy, motion_blur: to the bit
    if scene.moving:  # every object at each ray's time: the numpy engine takes its time
        scene = replace(scene, camera=replace(scene.camera, width=48, height=32))
    same_render(scene)


def test_the_compiled_engine_refuses_nothing_of_distributed_ray_tracing():
    assert all(compiled_refuses(load_scene(path)) is None for path in EXAMPLES)


@pytest.mark.parametrize("sampler", SAMPLERS)
@pytest.mark.parametrize("effect", ["area lights", "lens and mirrors", "flat", "glossy"])
def test_random_moving_scenes_render_the_same_with_both_engines(effect, sampler):
    rng = np.random.default_rng(sum(map(ord, "moving " + effect + sampler)))
    samples = {"random": 5, "jittered": 9, "sobol": 8}[sampler]
    scene = distributed_scene(
        rng, sampler, lens="lens" in effect, mirrors="mirrors" in effect or effect == "glossy",
        lights=effect != "flat", samples=samples, glossy=effect == "glossy", moving=True,
    )  # fmt: skip
    assert scene.moving and scene.blurred
    same_render(scene)


def test_a_moving_scene_of_more_objects_than_direct_hits_tests_every_one_through_its_tree():
    rng = np.random.default_rng(44)  # 14 spheres and 2 billboards: the tree's one leaf is walked
    scene = distributed_scene(rng, "sobol", lens=True, mirrors=True, moving=True, spheres=14)
    assert scene.object_count > compiled.DIRECT_HITS
    same_render(scene)


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_a_moving_scene_with_its_shutter_open_no_while_renders_the_same_with_both_engines(
    sampler,
):
    rng = np.random.default_rng(sum(map(ord, "shut " + sampler)))
    scene = distributed_scene(rng, sampler, mirrors=True, moving=True)
    shutter = (0.6, 0.6)  # every ray at T0: no time dimension in the numbers
    scene = replace(scene, sampling=replace(scene.sampling, shutter=shutter))
    assert scene.moving and not scene.blurred
    same_render(scene)


@pytest.mark.parametrize("sampler", SAMPLERS)
@pytest.mark.parametrize(
    "effect",
    ["area lights", "lens", "lens and mirrors", "area lights and mirrors", "flat lens", "glossy"],
)
def test_random_distributed_scenes_render_the_same_with_both_engines(effect, sampler):
    rng = np.random.default_rng(sum(map(ord, effect + sampler)))
    samples = {"random": 5, "jittered": 9, "sobol": 8}[sampler]
    scene = distributed_scene(
        rng, sampler, lens="lens" in effect, mirrors="mirrors" in effect or effect == "glossy",
        lights="flat" not in effect, samples=samples, glossy=effect == "glossy",
    )  # fmt: skip
    assert scene.distributed and (scene.area_lights > 0) == ("flat" not in effect)
    same_render(scene)


@pytest.mark.parametrize("sampler,samples", [("random", 257), ("jittered", 289), ("sobol", 512)])
def test_more_samples_a_pixel_than_a_batch_of_lanes_render_the_same_with_both_engines(
    sampler, samples
):
    """A pixel's samples in more than one batch of SAMPLED_LANES, its sums carried over."""
    assert samples > compiled.render.SAMPLED_LANES
    rng = np.random.default_rng(samples)
    scene = distributed_scene(rng, sampler, lens=True, mirrors=True, samples=samples)
    same_render(replace(scene, camera=replace(scene.camera, width=4, height=2)))


@pytest.mark.parametrize("sampler,samples,moving", [
    ("random", 1, False), ("jittered", 1, False), ("sobol", 1, False), ("sobol", 2, False),
    ("random", 3, False), ("sobol", 1, True),
])  # fmt: skip
def test_few_samples_a_pixel_in_jobs_across_rows_render_the_same_with_both_engines(
    sampler, samples, moving
):
    """With fewer samples a pixel than fill a batch's lanes, a job holds more pixels than
    SAMPLED_PIXELS (job_pixels), here running over the end of a row: its batches stop there.
    A scene that moves takes jobs of the same pixels, one sample at a time."""
    job = compiled.render.job_pixels(samples)
    assert job > compiled.render.SAMPLED_PIXELS
    rng = np.random.default_rng(samples * 7 + len(sampler))
    scene = distributed_scene(rng, sampler, samples=samples, moving=moving)
    assert scene.moving == moving
    width = job + 37  # a job ends inside a row, and the next runs into the row below
    same_render(replace(scene, camera=replace(scene.camera, width=width, height=3)))


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_an_orthographic_camera_with_an_area_light_renders_the_same_with_both_engines(sampler):
    scene = load_scene(SCENES / "orthographic.json")
    light = AreaLight(np.array([-1.0, 6.0, 2.0]), np.array([2.0, 0, 0]), np.array([0, 0, 1.5]),
                      np.array([0.8, 0.8, 0.7]))  # fmt: skip
    scene = replace(
        scene, camera=replace(scene.camera, width=48, height=36), lights=(light,),
        ambient=np.array([0.2, 0.2, 0.2]), sampling=Sampling(4, sampler, 7),
    )  # fmt: skip
    assert scene.distributed and scene.camera.projection == "orthographic"
    same_render(scene)


def test_a_distributed_scene_refuses_the_n_by_n_grid_in_one_line_with_either_engine():
    scene = load_scene(SCENES / "soft_shadows.json")
    messages = []
    for engine in ("numpy", "compiled"):
        with pytest.raises(ValueError, match="takes its samples from render.samples_per") as info:
            render(scene, samples=2, engine=engine)
        messages.append(str(info.value))
    assert messages[0] == messages[1] and "\n" not in messages[0]


def test_a_distributed_render_tells_progress_of_every_pixel_once():
    scene = distributed_scene(np.random.default_rng(3), "random", lens=True)
    told = []
    rgb, _, _ = compiled.render.render(scene, progress=told.append)
    assert sum(told) == 48 * 36 and len(told) > 1
    exactly(rgb, compiled.render.render(scene)[0])


def _picture_scenes():
    """A scene of each path the kernels take, 48 x 32 or 48 x 36 pixels, and its render's samples
    and adaptive: flat, one sample a pixel and an even n (no sample at the centre), lit and
    refined (its edges' samples as image points), mirrors, orthographic, and distributed: a
    pinhole's, a lens's, a moving one."""

    def example(name):
        scene = load_scene(SCENES / f"{name}.json")
        return replace(scene, camera=replace(scene.camera, width=48, height=32))

    rng = np.random.default_rng(60)
    return {
        "flat": (example("classic"), 1, False),
        "flat 2x2": (example("classic"), 2, False),
        "lit 3x3 adaptive": (example("classic_lit"), 3, True),
        "mirrors 2x2": (example("mirror_balls"), 2, False),
        "orthographic": (example("orthographic"), 1, False),
        "area lights": (distributed_scene(rng, "sobol"), 1, False),
        "lens and mirrors": (distributed_scene(rng, "random", lens=True, mirrors=True), 1, False),
        "moving": (distributed_scene(rng, "jittered", moving=True), 1, False),
    }


@pytest.mark.parametrize("kind", list(_picture_scenes()))
def test_the_picture_alone_is_the_picture_with_hits_of_every_path(kind):
    scene, samples, adaptive = _picture_scenes()[kind]
    whole = render(scene, samples, adaptive=adaptive, engine="compiled")
    told = []
    alone = render(scene, samples, adaptive=adaptive, engine="compiled", hits=False,
                   progress=told.append)  # fmt: skip
    assert alone.object_index is None and alone.t is None
    exactly(alone.rgb, whole.rgb)
    width, height = scene.camera.width, scene.camera.height
    assert sum(told) == width * height
    assert whole.object_index.shape == whole.t.shape == (height, width)


@pytest.mark.parametrize("samples,adaptive", [(2, False), (3, False), (3, True)])
@pytest.mark.parametrize("name", ["classic", "cutouts", "mirror_balls", "orthographic"])
def test_samples_and_adaptive_sampling_give_the_same_image_with_both_engines(
    name, samples, adaptive
):
    scene = load_scene(SCENES / f"{name}.json")
    small = replace(scene, camera=replace(scene.camera, width=96, height=72))
    same_render(small, samples=samples, adaptive=adaptive)


@pytest.mark.parametrize("objects", [5, 200])
def test_random_crowds_render_the_same_with_both_engines(objects):
    same_render(crowd(np.random.default_rng(objects + 1), objects))


def test_far_tiny_sphere_and_a_scene_at_1e6_render_the_same_with_both_engines():
    fov = float(np.degrees(4e-8))
    far = {
        "camera": {"eye": [0, 0, 1e5], "lookat": [2e-4, -1e-4, 0], "up": [0, 1, 0],
                   "fov_angle": fov, "width": 23, "height": 23},
        "spheres": [{"center": [0, 0, 0], "radius": 1e-3, "color": [1, 1, 1]}],
    }  # fmt: skip
    same_render(scene_from_dict(far))
    data = json.loads((SCENES / "classic_lit.json").read_text())
    data.pop("$schema", None)
    moved = scene_from_dict(shifted_scene(data, [1e6, 1e6, 1e6]), folder=SCENES)
    same_render(replace(moved, camera=replace(moved.camera, width=120, height=90)))


@two_threads()
def test_the_image_does_not_depend_on_which_core_takes_which_tile():
    scenes = [packet_scenes()["classic_lit_at_1e6"], crowd(np.random.default_rng(11), 200)]
    mirrors = load_scene(SCENES / "mirror_balls.json")
    scenes.append(replace(mirrors, camera=replace(mirrors.camera, width=80, height=60)))
    rng = np.random.default_rng(12)  # distributed: a pixel's numbers are its own, whoever takes it
    scenes += [distributed_scene(rng, sampler, lens=True, mirrors=True) for sampler in SAMPLERS]
    scenes += [distributed_scene(rng, sampler, spheres=12) for sampler in SAMPLERS]  # tiles
    scenes += [distributed_scene(rng, sampler, lens=True, mirrors=True, moving=True)
               for sampler in SAMPLERS]  # fmt: skip
    threads = numba.get_num_threads()
    try:
        for scene in scenes:
            prepared = compiled.prepare(scene)
            numba.set_num_threads(1)
            samples = 1 if scene.distributed else 2
            rgb, index, t = compiled.render.render(prepared, samples)
            numba.set_num_threads(threads)
            for progress in (None, lambda rows: None) * 3:  # one call, or one per band of rows
                again = compiled.render.render(prepared, samples, progress=progress)
                assert np.array_equal(again[1], index)
                exactly(again[2], t)
                exactly(again[0], rgb)
    finally:
        numba.set_num_threads(threads)


def test_every_kind_of_scene_hands_the_kernels_arrays_of_one_kind():
    # numba compiles the kernels again (minutes) for each new kind of array, read-only included
    plain = {
        "camera": {"eye": [0, 0, 6], "lookat": [0, 0, 0], "up": [0, 1, 0], "fov_angle": 50,
                   "width": 32, "height": 24},
        "spheres": [{"center": [x, 0, 0], "radius": 0.5, "color": [1, 0, 0]} for x in (-1, 1)],
    }  # fmt: skip
    scenes = {
        "named spheres, textures": load_scene(SCENES / "classic.json"),
        "lights, mirrors": load_scene(SCENES / "mirror_balls.json"),
        "plain spheres, kept as read-only columns": scene_from_dict(plain),
        "billboards only": replace(load_scene(SCENES / "cutouts.json"), spheres=()),
        "crowd": crowd(np.random.default_rng(5), 50),
    }
    kinds = {name: numba.typeof(compiled.prepare(scene)[1:]) for name, scene in scenes.items()}
    assert len(set(kinds.values())) == 1, kinds


@contextlib.contextmanager
def arguments_typed_in_python():
    """The names of the kernels whose arguments numba types in Python (its slow path) while in
    the block. Numba's dispatcher finds the compiled code for a call by a fingerprint of its
    arguments' types, in C; an argument it cannot fingerprint, or one whose fingerprint another
    class took first (a NamedTuple of the same name and fields), is typed in Python on every
    call."""
    from numba.core.dispatcher import _DispatcherBase

    typed = []
    typeof_pyval = _DispatcherBase.typeof_pyval

    def counted(dispatcher, value):
        typed.append(dispatcher.py_func.__name__)
        return typeof_pyval(dispatcher, value)

    _DispatcherBase.typeof_pyval = counted
    try:
        yield typed
    finally:
        _DispatcherBase.typeof_pyval = typeof_pyval


def test_numba_types_in_python_a_namedtuple_whose_name_and_fields_another_class_took():
    # why the benchmark of the engine before and after (benchmarks/compile_time.py) runs
    # each engine in a process of its own, and the control for the test below
    from typing import NamedTuple

    class Pair(NamedTuple):
        a: float
        b: float

    first = Pair

    class Pair(NamedTuple):  # noqa: F811 (the point: a second class of the same name)
        a: float
        b: float

    def total(pair):
        return pair.a + pair.b

    # each class to a kernel of its own, as each engine passes its own to its own kernels
    total_of_first, total_of_second = numba.njit(total), numba.njit(total)
    total_of_first(first(1.0, 2.0))
    total_of_second(Pair(1.0, 2.0))
    with arguments_typed_in_python() as typed:
        assert total_of_first(first(1.0, 2.0)) == 3.0
    assert typed == []
    with arguments_typed_in_python() as typed:
        assert total_of_second(Pair(1.0, 2.0)) == 3.0
    assert typed == ["total"]


@pytest.mark.parametrize("name", ["classic.json", "shadow_on_billboard.json"])
def test_a_prepared_render_finds_its_kernels_without_typing_an_argument_in_python(name):
    prepared = compiled.prepare(load_scene(SCENES / name))
    compiled.render.render(prepared)  # loads the kernels (their first call types its arguments)
    with arguments_typed_in_python() as typed:
        compiled.render.render(prepared)
    assert typed == []


def test_a_prepared_render_asks_nothing_more_of_every_object(monkeypatch):
    """Whether a scene is distributed is asked of every object's material once, not at each
    render of the prepared scene: on sphereflake 6 that question took as long as the rays."""
    from raykit.materials import MaterialTable

    prepared = compiled.prepare(load_scene(SCENES / "classic.json"))
    compiled.render.render(prepared)

    def asked_again(table):
        raise AssertionError("a material column was read again")

    for question in ("any_glossy", "any_mirror", "any_shiny"):
        monkeypatch.setattr(MaterialTable, question, property(asked_again))
    compiled.render.render(prepared)


def test_a_lit_scene_without_mirrors_never_types_the_mirror_rays():
    """A scene compiles only what it uses: a lit scene with no mirror passes lit_job ``bounces``
    None, and numba's pruning of branches on argument types, run before typing, drops the call
    of mirror_rays (so it is never typed, compiled or linked); a scene with mirrors keeps it, and
    its entry point is named apart (its own marker and progress line), as
    :func:`raykit.engine.choice.entry_point` names it. (Checked on the IR: which kernels a
    process compiles depends on what its cache already holds.)"""
    from numba.core import ir, types
    from numba.core.analysis import dead_branch_prune
    from numba.core.compiler import run_frontend

    from raykit.engine.compiled import shading as kernels

    parameters = list(inspect.signature(compiled.render.lit_job.py_func).parameters)

    def calls_mirror_rays(bounces) -> bool:
        kind = types.none if bounces is None else types.boolean
        lit_job = run_frontend(compiled.render.lit_job.py_func)
        dead_branch_prune(lit_job, tuple(kind if p == "bounces" else types.pyobject
                                         for p in parameters))  # fmt: skip
        return any(
            isinstance(statement.value, ir.Global) and statement.value.value is kernels.mirror_rays
            for block in lit_job.blocks.values()
            for statement in block.find_insts(ir.Assign)
        )

    seen = []
    for name in ("classic", "classic_lit", "mirror_balls"):
        scene = load_scene(SCENES / f"{name}.json")
        entry, _, leading = compiled.render._entry(compiled.prepare(scene))
        seen.append((entry, calls_mirror_rays(leading[-1]) if entry != "trace_flat" else None))
    assert seen == [("trace_flat", None), ("trace_lit", False), ("trace_mirrors", True)]


def test_a_still_distributed_scene_never_types_the_moving_scenes_or_mirrors_kernels():
    """As above, for stage 5: a scene whose spheres stand still renders by trace_sampled, which
    calls no sampled_job (the moving scene's, trace_moving's), and without mirrors passes
    sampled_lanes ``bounces`` None, whose pruning drops bounce_on; glossy.json keeps it. Each
    kind is an entry point of its own (its marker, its progress line)."""
    import inspect

    from numba.core import ir, types
    from numba.core.analysis import dead_branch_prune
    from numba.core.compiler import run_frontend

    from raykit.engine.compiled import shading as kernels

    def globals_called(kernel, bounces) -> set:
        parameters = list(inspect.signature(kernel.py_func).parameters)
        kind = types.none if bounces is None else types.boolean
        code = run_frontend(kernel.py_func)
        dead_branch_prune(code, tuple(kind if p == "bounces" else types.pyobject
                                      for p in parameters))  # fmt: skip
        return {
            statement.value.value
            for block in code.blocks.values()
            for statement in block.find_insts(ir.Assign)
            if isinstance(statement.value, ir.Global)
        }

    seen = []
    for name in ("soft_shadows", "glossy", "motion_blur"):
        entry, trace, leading = compiled.render._entry(
            compiled.prepare(load_scene(SCENES / f"{name}.json"))
        )
        called = globals_called(
            trace, leading[-1] if trace is compiled.render.trace_sampled else None
        )
        lanes = compiled.render.sampled_lanes in called
        bounces = lanes and kernels.bounce_on in globals_called(
            compiled.render.sampled_lanes, leading[-1]
        )
        seen.append((entry, compiled.render.sampled_job in called, lanes, bounces))
    assert seen == [
        ("trace_sampled", False, True, False),
        ("trace_sampled_mirrors", False, True, True),
        ("trace_moving", True, False, False),
    ]


def test_a_second_render_reuses_the_first_ones_memory():
    """A render's outputs (a 1080p picture's are 83 MB) come from the memory the last one's
    left, not from new pages of the system, each a fault and zeroed (glibc's malloc keeps
    what is freed: compiling.keep_freed_memory). Counted by the process's page faults."""
    run = run_python(
        "import resource\n"
        "from dataclasses import replace\n"
        "from raykit.engine import compiled\n"
        "from raykit.io.scene_json import load_scene\n"
        "scene = load_scene('scenes/classic.json')\n"
        "scene = replace(scene, camera=replace(scene.camera, width=1920, height=1080))\n"
        "prepared = compiled.prepare(scene)\n"
        "for _ in range(3):\n"
        "    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt\n"
        "    image = compiled.render.render(prepared)\n"
        "    del image\n"
        "print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)\n"
    )
    assert run.returncode == 0, run.stderr
    assert int(run.stdout) < 100  # new pages for the outputs: 20,000 of 4 KB, or 40 of 2 MB


# the kinds of scene the example scenes and the crowds above never render, and the first eight
# scenes random_scene makes from seed 26 all have between them (with an adaptive render): one
# image 1 pixel wide or so, a 1 or 179 degree view, the camera in a sphere, a billboard edge-on
# to the eye, lights in and on objects, mirrors with no light, 1,500 objects, tiny spheres...
KINDS_NEVER_RENDERED_ELSEWHERE = {
    "odd image size (1x1, 1x37, 97x3, ...)",
    "fov_angle 1, 2.5, 160 or 179 degrees",
    "camera inside a sphere",
    "billboard edge-on to the eye",
    "point light on a surface",
    "point light inside an object",
    "materials, no lights nor ambient",
    "401 to 1,500 objects",
    "tiny spheres on pixels' rays (radius 1e-5 to 1e-4)",
    "object behind the camera",
    "mirrors, max_depth 4",
}


def test_random_scenes_of_every_kind_render_the_same_with_both_engines(tmp_path):
    from random_scenes import make_textures, random_scene

    rng = np.random.default_rng(26)
    textures = make_textures(rng, tmp_path / "textures")
    kinds, adaptive = set(), False
    for _ in range(8):
        data, options, tags = random_scene(rng, textures)
        kinds |= tags
        adaptive |= options["adaptive"]
        same_render(scene_from_dict(data, folder=tmp_path), **options)
    assert KINDS_NEVER_RENDERED_ELSEWHERE <= kinds and adaptive


def _distributed(sampler, **effects):
    return lambda rng: same_render(distributed_scene(rng, sampler, **effects))


def _in_lanes(rng):
    """A distributed scene's samples in lanes: glossy mirrors; past DIRECT_HITS objects, the
    viewing rays of a crowded row of pixels, or of a lens, through the tree; past
    SHADOW_CANDIDATES, the shadow rays too."""
    same_render(distributed_scene(rng, "sobol", mirrors=True, glossy=True))
    same_render(distributed_scene(rng, "random", spheres=12))
    same_render(distributed_scene(rng, "jittered", lens=True, spheres=18))


def test_a_pinholes_distributed_scene_has_screen_tiles_and_a_lenss_or_a_moving_ones_none():
    """The tile path is the one a pinhole's samples take (row_objects lists each batch's
    objects): same_render would pass as well without it, the hits being the same."""
    rng = np.random.default_rng(57)
    pinhole = compiled.prepare(distributed_scene(rng, "sobol", spheres=12))
    assert len(pinhole.tiles.start) > 1 and pinhole.tiles.size == compiled.render.SAMPLED_SIDE
    near = np.empty(8, dtype=np.int64)
    camera = pinhole.scene.camera
    listed = np.array([compiled.tiles.row_objects(pinhole.tiles, camera.width, p, p + 15, near)
                       for p in range(0, camera.width * camera.height, 16)])  # fmt: skip
    assert np.mean(listed >= 0) > 0.9 and listed.max() < pinhole.scene.object_count
    for effects in ({"lens": True}, {"moving": True}):
        assert len(compiled.prepare(distributed_scene(rng, "sobol", **effects)).tiles.start) == 1


def _nearby(rng):
    """A pinhole's distributed samples, each batch of them tested against the objects its pixels'
    screen tiles list (row_objects): few enough to test in lanes, or, past DIRECT_HITS, each ray
    through the tree; with a lens, every object; flat and shaded."""
    same_render(distributed_scene(rng, "random", lights=False, spheres=12))
    same_render(distributed_scene(rng, "sobol", spheres=40, samples=16))
    same_render(distributed_scene(rng, "jittered", lens=True, lights=False))


CHECKS = {
    "render.trace_sampled": _distributed("jittered", lens=True, mirrors=True),
    "render.trace_moving": _distributed("jittered", lights=False, moving=True),
    "render.sampled_job": _distributed("sobol", mirrors=True, glossy=True, moving=True),
    "render.sampled_lanes": _in_lanes,
    "render.cast_lanes": _nearby,
    "render.cast_batch": _nearby,
    "render.cast_each": _in_lanes,
    "render.cast_rays": caster_answers_what_cast_answers,
    "render.trace_flat": small_render("classic"),
    "render.flat_job": small_render("cutouts"),
    "render.trace_lit": small_render("classic_lit"),
    "render.lit_job": small_render("mirror_balls"),
    "render.spheres_at": _distributed("random", lens=True, mirrors=True, moving=True),
}
test_the_twin_repeats_its_reference = twin_test("render", CHECKS)

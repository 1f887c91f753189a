"""raykit against Mitsuba 3 on the same scenes, in one run: load and render times, 1 sample
per pixel, pure ray casting (flat scenes) and direct lighting with shadows (lit scenes).

    python benchmarks/mitsuba_compare.py [--quick] [--repeats N] [--plot mitsuba_compare.png]
        [--cpu native haswell] [--threads N [N ...]] [--pictures FOLDER]

Mitsuba is an optional benchmark dependency, never a runtime one (``pip install mitsuba``).
Its ``llvm_ad_rgb`` variant needs an LLVM it can load: on Debian 12, ``apt install libllvm19``
and ``DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1`` (Debian's default LLVM
15 makes it abort). Each Mitsuba variant runs in a child process of its own, so a variant that
aborts is reported as such and the run goes on.

The scenes are raykit's, converted: spheres to Mitsuba spheres; billboards to rectangles whose
``to_world`` maps [-1, 1]² onto the parallelogram; the camera to a ``perspective`` sensor with
the same eye, lookat, up and vertical fov. Mitsuba renders with its ``depth`` integrator (the
distance to the nearest hit: the same ray casting as raykit's object image, without texture
lookups); raykit renders its flat colours, textures included. Mitsuba's sampler jitters each
pixel's one sample, raykit takes the pixel centre, so their hit masks differ at silhouettes:
the table gives the share of pixels on which both agree whether anything is hit.

Lit scenes (a second table): classic, sphereflake 4 and 1,000 spheres, each with two point
lights (:data:`LIGHTS`), shadows on, no ambient light, and diffuse surfaces only (each object's
colour its kd; a textured billboard plain grey, :func:`lit`), so that both renderers do the
same work: a viewing ray, then per hit one shadow ray per light and a Lambert term. Mitsuba
renders them with its ``direct`` integrator, ``emitter_samples`` = 2 (the number of lights),
``bsdf_samples`` = 0, ``point`` emitters and ``diffuse`` BSDFs (``twosided`` on billboards,
which raykit lights on the side the ray comes from). The radiometry differs, and is matched
only at one distance: raykit's point light does not fall off and its Lambert term is
kd·I·cos; Mitsuba's falls off with r² and its diffuse BSDF is kd/π, so its intensity is
π·I·r0², r0 the light's distance to the camera's lookat point (:func:`mitsuba_intensity`).
And Mitsuba's direct integrator picks a light at random for each emitter sample (weighted by
the count): the same two shadow rays per hit, but a noisy picture, where raykit's takes each
light once. The pictures' check (untimed) therefore renders in Mitsuba each pixel's centre
(``stratified``, no jitter) with each light alone, multiplies each by (r/r0)², r the distance
from the light to raykit's hit point, adds them, and compares with raykit's render:
the table gives the hit masks' agreement and the mean absolute difference of linear colours
over the pixels both hit (:func:`agreement`). ``--pictures FOLDER`` saves raykit's picture,
Mitsuba's timed one and Mitsuba's as raykit's radiometry would make it, per lit scene.
Mitsuba's ``llvm_ad_rgb`` direct render of a scene of many shapes costs a time per render that
grows with the number of shapes and hardly with the pixels (lit sphereflake 4 takes about as
long at 128x128 as at 512x512; its depth render does not): its lit sphereflake row measures
that more than ray work, which its ``scalar_rgb`` row shows better. Giving the spheres of one
colour one shared BSDF did not change it.

Instruction sets. ``--cpu native haswell`` makes a run for each, one after the other, each
in a process of its own, on one page (``--cpu haswell`` alone: the AVX2 run only). native: every
compiler picks the processor it finds. haswell (AVX2, no AVX-512, as on the AMD EPYC the
issue quotes): numba compiles for haswell with haswell's own features (``NUMBA_CPU_NAME``,
``NUMBA_CPU_FEATURES``, set before numba is imported: :func:`run_for`; numba caches these
kernels apart from the native ones), Dr.Jit's LLVM backend targets haswell with 8 lanes
(:func:`drjit_target`, through its core library: its Python API has no call for it), and
Mitsuba's Embree, which does the BVH walk of both variants and picks its instruction set at
run time, is told ``isa=avx2`` by a small library preloaded into Mitsuba's children
(:func:`embree_avx2`, compiled with the C compiler; without one, Embree keeps its own pick and
the page says so). Mitsuba's other ahead-compiled code, all of ``scalar_rgb`` but Embree, is
as shipped. Each run's page section names the processor and the instruction set.

Threads. ``--threads N`` gives every renderer N threads: raykit's compiled engine N numba
threads, each Mitsuba variant a Dr.Jit thread pool of N (``drjit.set_thread_count``, which
both variants render with); by default each takes every core. ``--threads 1 2`` makes a run for
each count, one after the other, each a section of the page, and ends the page with raykit
compiled's ratios to Mitsuba llvm side by side, a column pair per count (:func:`summary`). On
a shared machine, one thread each times the work more steadily: a render in many threads waits
at its end for the slowest, and one that a neighbour holds up waits for the scheduler's next
turn.

Load: raykit from the scene's file (:func:`set_up_raykit`: the JSON read and checked, each
texture's header read; a median of 3), Mitsuba ``load_dict`` (which builds its BVH, and reads
and decodes each texture: a ``bitmap`` on its billboard's BSDF, though its depth integrator
looks none up, so that from the file both do the same steps). Prepare, raykit's compiled engine
only: ``raykit.engine.compiled.prepare`` of a scene just loaded, its textures' texels got, the
scene's arrays, screen tiles and (lit scenes) BVH (a median of 3); so load + prepare is what
raykit does from the file before its first ray, as load_dict is Mitsuba's. A texture of 256²
texels or more comes from raykit's cache of decoded textures once any render has decoded it
(:mod:`raykit.io.textures`), as it does for a second render of the same file: the table's
prepare is that one, and a line below the flat table gives the textured scene's prepare with the
cache empty, every texture decoded (:func:`cold_prepare`). The flat scenes include classic with
each texture 256 x 256 RGBA (:func:`scenes.classic_with_large_textures`). Its render renders the
prepared scene, as Mitsuba's renders its loaded one (``raykit.render.render`` does both). Each
timed render, raykit's and Mitsuba's, makes the picture alone: raykit's with ``hits=False``, no
object index and t per pixel (which a render keeps by default, and which Mitsuba's depth
integrator does not make), as ``raykit render`` renders a PNG; the agreement check takes them
from an untimed render.
Render: the median of ``--repeats`` renders after a first one (for ``llvm_ad_rgb`` the first
compiles its kernels; it is shown too), every renderer of a scene in turns, so that the
machine's other work falls on all alike (:func:`common.medians_in_turns`; each timed render
right after an untimed one of its own). Each Mitsuba variant stays in its child process for the
whole scene and times its own renders there, on request.

The last line checks the growth goals: sphereflake 4 to 6 in at most 3x the render time, level
6 loaded, prepared and rendered in 2 s. The growth ratio is timed anew, the two prepared
sphereflakes rendered in turns in the same way, since the table times each scene at its own
time, and this machine's neighbours make those times vary.
``--plot`` draws the render medians as bars per scene, one per renderer (raykit's alone when
Mitsuba is not installed).
"""

from __future__ import annotations

import argparse
import json
import os
import select
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import (  # noqa: E402
    arguments,
    bar_plot,
    median_time,
    medians_in_turns,
    numba_cpu,
    parse,
    processor,
    seconds,
    sized,
    timer,
)

from raykit.camera import rays_through  # noqa: E402
from raykit.engine.choice import ENGINES  # noqa: E402
from raykit.io.images import save_image  # noqa: E402
from raykit.io.scene_json import load_scene, scene_from_dict  # noqa: E402
from raykit.lights import PointLight  # noqa: E402
from raykit.rays import dot  # noqa: E402
from raykit.render import render  # noqa: E402
from raykit.scene import Scene  # noqa: E402
from scenes import (  # noqa: E402
    TEXTURE_SIDE,
    classic_with_large_textures,
    many_spheres,
    sphereflake,
)

VARIANTS = ("scalar_rgb", "llvm_ad_rgb")
LLVM_19 = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"


def benchmark_scenes(quick: bool, folder: Path | None = None) -> dict[str, Scene]:
    """The flat scenes, by name; with ``folder``, classic with 256² textures too, its scene
    file and textures written there (:func:`scenes.classic_with_large_textures`)."""
    if quick:
        return {
            "classic 160x120": sized(load_scene(HERE.parent / "scenes/classic.json"), 160, 120),
            "sphereflake 2 128x128": sphereflake(2, 128, 128),
        }
    textured = {}
    if folder is not None:
        path = classic_with_large_textures(folder)
        textured = {f"classic, {TEXTURE_SIDE}² textures, 640x480": load_scene(path)}
    return {
        "classic 640x480": load_scene(HERE.parent / "scenes/classic.json"),
        **textured,
        "sphereflake 4 512x512": sphereflake(4),
        "1,000 spheres 1920x1080": many_spheres(1000),
        "sphereflake 6 512x512": sphereflake(6),
    }


# Two point lights per lit scene, by the start of the flat scene's name: (position, intensity
# I in raykit's sense, no fall-off), placed above and to the sides of what the camera sees
LIGHTS = {
    "classic": (([4.0, 6.0, 5.0], [0.6, 0.6, 0.55]), ([-5.0, 4.0, 3.0], [0.35, 0.35, 0.4])),
    "sphereflake": (([4.0, 6.0, 2.0], [0.6, 0.6, 0.55]), ([-3.0, 4.0, 4.0], [0.35, 0.35, 0.4])),
    "1,000 spheres": (([-6.0, 8.0, 0.0], [0.6, 0.6, 0.55]), ([8.0, 2.0, -12.0], [0.35, 0.35, 0.4])),
}
STAND_IN = [0.6, 0.6, 0.6]  # a textured billboard's diffuse colour in a lit scene


def lit_scenes(quick: bool) -> dict[str, Scene]:
    """The lit versions of the bench scenes (sphereflake 6 aside: its Mitsuba BVH alone takes a
    minute), each with the two point lights of :data:`LIGHTS` (:func:`lit`)."""
    return {
        f"{name} lit": lit(scene, next(v for k, v in LIGHTS.items() if name.startswith(k)))
        for name, scene in benchmark_scenes(quick).items()
        if not name.startswith("sphereflake 6")
    }


def lit(scene: Scene, lights) -> Scene:
    """``scene`` lit by point ``lights`` ((position, intensity), ...), shadows on, no ambient
    light, and diffuse only: each object's flat colour is its kd, no highlight, no mirror. A
    textured billboard takes the plain colour :data:`STAND_IN` instead of its texture: its
    cut-out texels would need an alpha-masked BSDF in Mitsuba, work of another kind."""
    data = scene_data(scene)
    for board in data["billboards"]:
        if board.pop("image", None) is not None:
            board["color"] = STAND_IN
    data["lights"] = [{"type": "point", "position": p, "color": c} for p, c in lights]
    return scene_from_dict(data)


def scene_data(scene: Scene) -> dict:
    """The scene as plain data: raykit's JSON fields (flat colours; textures as their
    paths; point lights), enough to rebuild it with ``scene_from_dict`` and to convert it for
    Mitsuba."""
    camera = scene.camera
    return {
        "camera": {
            "eye": list(map(float, camera.eye)),
            "lookat": list(map(float, camera.lookat)),
            "up": list(map(float, camera.up)),
            "fov_angle": camera.fov_angle,
            "width": camera.width,
            "height": camera.height,
        },
        "background": list(map(float, scene.background)),
        "spheres": [
            {
                "center": list(map(float, s.center)),
                "radius": float(s.radius),
                "color": list(map(float, s.color)),
            }
            for s in scene.spheres
        ],
        "billboards": [
            {
                "upper_left": list(map(float, b.upper_left)),
                "lower_left": list(map(float, b.lower_left)),
                "upper_right": list(map(float, b.upper_right)),
                **(
                    {"image": str(b.texture.path)}
                    if b.texture
                    else {"color": list(map(float, b.color))}
                ),
            }
            for b in scene.billboards
        ],
        **({"lights": _point_lights(scene), "shadows": scene.shadows} if scene.lights else {}),
    }


def _point_lights(scene: Scene) -> list[dict]:
    """The scene's lights as data: point lights only, the kind the lit scenes have."""
    if scene.ambient is not None or not all(isinstance(x, PointLight) for x in scene.lights):
        raise ValueError("only point lights, without ambient light, are converted for Mitsuba")
    return [
        {
            "type": "point",
            "position": list(map(float, x.position)),
            "color": list(map(float, x.color)),
        }
        for x in scene.lights
    ]


def mitsuba_dict(
    data: dict, mi, *, only_light: int | None = None, depth: bool = False, centres: bool = False
) -> dict:
    """Mitsuba's scene description of raykit scene data (see the module page): a flat scene for
    the ``depth`` integrator, a lit one for ``direct`` with one shadow ray per light per hit
    (an area light a rectangle emitter, :func:`mitsuba_light`); a camera with an ``aperture``
    is a ``thinlens`` sensor (``benchmarks/race.py``'s scenes). For the pictures'
    check only: ``only_light`` keeps that light alone, ``depth`` renders
    distances whatever the scene, ``centres`` samples each pixel at its centre, as raykit does,
    instead of at a random point."""
    camera = data["camera"]
    lights = data.get("lights", [])
    if lights and not depth:
        count = len(lights) if only_light is None else 1
        integrator = {"type": "direct", "emitter_samples": count, "bsdf_samples": 0}
    else:
        integrator = {"type": "depth"}
    sampler = (
        {"type": "stratified", "sample_count": 1, "jitter": False}
        if centres
        else {"type": "independent", "sample_count": 1}
    )
    scene = {
        "type": "scene",
        "integrator": integrator,
        "sensor": {
            "type": "perspective",
            "fov": camera["fov_angle"],
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=camera["eye"], target=camera["lookat"], up=camera["up"]
            ),
            "film": {
                "type": "hdrfilm",
                "width": camera["width"],
                "height": camera["height"],
                "rfilter": {"type": "box"},
            },
            "sampler": sampler,
        },
    }

    def diffuse(color: list) -> dict:
        return {"type": "diffuse", "reflectance": {"type": "rgb", "value": color}}

    for i, s in enumerate(data["spheres"]):
        scene[f"sphere{i}"] = {"type": "sphere", "center": s["center"], "radius": s["radius"]}
        if lights:
            scene[f"sphere{i}"]["bsdf"] = diffuse(s["color"])
    for i, b in enumerate(data["billboards"]):
        ul, ll, ur = (np.array(b[k]) for k in ("upper_left", "lower_left", "upper_right"))
        scene[f"billboard{i}"] = rectangle(ul, ur - ul, ll - ul, mi)
        if lights:  # a billboard is lit on the side its ray comes from, as raykit's
            scene[f"billboard{i}"]["bsdf"] = {"type": "twosided", "bsdf": diffuse(b["color"])}
        elif "image" in b:  # read and decoded by load_dict, as raykit's load and prepare do
            texture = {"type": "bitmap", "filename": b["image"]}
            scene[f"billboard{i}"]["bsdf"] = {"type": "diffuse", "reflectance": texture}
    for i, light in enumerate(lights):
        if only_light is None or i == only_light:
            scene[f"light{i}"] = mitsuba_light(light, camera, mi)
    if camera.get("aperture"):  # raykit's thin lens: its aperture is the lens's diameter
        scene["sensor"]["type"] = "thinlens"
        scene["sensor"]["aperture_radius"] = camera["aperture"] / 2
        scene["sensor"]["focus_distance"] = camera.get("focus_distance") or _distance(
            camera["eye"], camera["lookat"]
        )
    return scene


def rectangle(corner: np.ndarray, a: np.ndarray, b: np.ndarray, mi, facing=None) -> dict:
    """Mitsuba's ``rectangle`` whose ``to_world`` maps [-1, 1]² onto the parallelogram with
    ``corner`` and edges ``a``, ``b`` ``(3,)`` (a billboard, an area light). Its front, the side
    an area emitter lights, is a × b's; ``facing`` (a point ``(3,)``): the side that point is on."""
    n = np.cross(a, b)
    n = n / np.linalg.norm(n)
    # Mitsuba's normal follows the third column (it maps normals by the inverse transpose)
    if facing is not None and float(np.sum(n * (np.asarray(facing) - corner))) < 0:
        n = -n
    matrix = np.eye(4)
    matrix[:3, 0], matrix[:3, 1], matrix[:3, 2] = a / 2, b / 2, n
    matrix[:3, 3] = corner + (a + b) / 2
    return {"type": "rectangle", "to_world": mi.ScalarTransform4f(matrix.tolist())}


def mitsuba_light(light: dict, camera: dict, mi) -> dict:
    """Mitsuba's light for raykit's ``light`` (data): a point light of intensity
    :func:`mitsuba_intensity`; for a physically based area light (its ``radiance``), a
    ``rectangle`` with an ``area`` emitter of that radiance lighting the side a × b points to,
    the same light (:func:`raykit.lights.area_intensity`); for FOCG's area light, such an
    emitter lighting the side the camera's lookat point is on, of radiance
    :func:`mitsuba_radiance`, a light that matches raykit's at lookat only."""
    if light["type"] == "point":
        intensity = mitsuba_intensity(light, camera)
        return {
            "type": "point",
            "position": light["position"],
            "intensity": {"type": "rgb", "value": intensity.tolist()},
        }
    c, a, b = (np.asarray(light[k], float) for k in ("corner", "edge1", "edge2"))
    if "radiance" in light:
        shape, radiance = rectangle(c, a, b, mi), np.asarray(light["radiance"], float)
    else:
        shape = rectangle(c, a, b, mi, facing=camera["lookat"])
        radiance = mitsuba_radiance(light, camera)
    return {
        **shape,
        "emitter": {"type": "area", "radiance": {"type": "rgb", "value": radiance.tolist()}},
    }


def mitsuba_radiance(light: dict, camera: dict) -> np.ndarray:
    """The radiance ``(3,)`` of Mitsuba's area emitter that matches raykit's area ``light`` at
    the camera's lookat point. raykit's area light, sampled, is a point light at each of its
    points, with no fall-off and no cosine at the light (:mod:`raykit.lights`): kd·I·cos at the
    surface. Mitsuba's emitter of radiance L and area A gives about
    (kd/π)·L·A·cos·cos_l/r² there, cos_l the cosine at the light, r the distance, both from
    the light's centre to lookat; L = π·I·r²/(A·cos_l) makes them equal at lookat (elsewhere
    they differ by the fall-off and the cosine at the light, so Mitsuba's picture is its own:
    the benchmark compares each renderer's error against its own reference)."""
    c, a, b = (np.asarray(light[k], float) for k in ("corner", "edge1", "edge2"))
    normal = np.cross(a, b)
    area = float(np.sqrt(np.sum(normal * normal)))
    to_lookat = np.asarray(camera["lookat"], float) - (c + (a + b) / 2)
    r2 = float(np.sum(to_lookat * to_lookat))
    cos_l = abs(float(np.sum(normal * to_lookat))) / (area * np.sqrt(r2))
    return np.pi * np.asarray(light["color"], float) * r2 / (area * cos_l)


def mitsuba_intensity(light: dict, camera: dict) -> np.ndarray:
    """The intensity of Mitsuba's point light ``(3,)`` that matches raykit's ``light`` at the
    camera's lookat point. raykit's point light does not fall off (:mod:`raykit.lights`), and
    its Lambert term is kd·I·cos; Mitsuba's falls off with the squared distance r², and its
    diffuse BSDF is kd/π, so it gives kd·I'·cos/(π r²). I' = π·I·r0², r0 the light's distance
    to lookat, makes them equal at that distance; at a point r away Mitsuba's is (r0/r)² of
    raykit's (:func:`agreement` undoes that factor per pixel)."""
    r0 = _distance2(light["position"], camera["lookat"])
    return np.pi * np.asarray(light["color"], float) * r0


def _distance2(a, b) -> float:
    return sum((float(x) - float(y)) ** 2 for x, y in zip(a, b, strict=True))


def _distance(a, b) -> float:
    return _distance2(a, b) ** 0.5


def mitsuba_child(variant: str, cpu: str, threads: int | None = None) -> None:
    """In a child process: load the scene (JSON, the first line of standard input) with one
    Mitsuba variant and render it once; print ``{"load", "first", "hit", "target"}`` as a line
    of JSON; then for each line ``render`` read, render once more and print the seconds it
    took; for a line ``check PATH``, write the pictures of :func:`check_pictures` to PATH (an
    .npz file) and print 1. The lines go to what was standard output when the child started;
    anything a library prints there goes to standard error instead, so it cannot be read as
    an answer. ``cpu``: "haswell" restricts Dr.Jit's kernels to AVX2 (:func:`drjit_target`);
    ``threads``: the size of Dr.Jit's thread pool (None: one thread a core)."""
    answers = answer_stream()
    import drjit
    import mitsuba as mi

    mi.set_variant(variant)
    if threads:
        drjit.set_thread_count(threads)
    target = drjit_target(cpu) if variant.startswith("llvm") else None
    data = json.loads(sys.stdin.readline())
    start = time.perf_counter()
    scene = mi.load_dict(mitsuba_dict(data, mi))
    load = time.perf_counter() - start
    start = time.perf_counter()
    image = np.array(mi.render(scene, spp=1))
    first = time.perf_counter() - start
    hit = (image[..., 0] > 0).tolist()
    made = {"load": load, "first": first, "hit": hit, "target": target}
    print(json.dumps(made), file=answers, flush=True)
    for line in sys.stdin:
        request = line.split()
        if request == ["render"]:
            start = time.perf_counter()
            np.array(mi.render(scene, spp=1))
            print(time.perf_counter() - start, file=answers, flush=True)
        elif request[:1] == ["check"]:
            np.savez(request[1], image=image[..., :3], **check_pictures(data, mi))
            print(1, file=answers, flush=True)


def answer_stream():
    """In a Mitsuba child: the stream its answers go to, what was standard output when it
    started; standard output goes to standard error from here on, so that anything a library
    prints there cannot be read as an answer."""
    answers = os.fdopen(os.dup(sys.stdout.fileno()), "w")
    sys.stdout.flush()
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    return answers


def check_pictures(data: dict, mi) -> dict:
    """What :func:`agreement` compares, rendered with each pixel sampled at its centre:
    ``depth (H, W)`` (0 where nothing is hit), and ``lights (L, H, W, 3)``, the picture lit by
    each light alone (one light: no random choice of light, so no noise)."""

    def picture(**kind) -> np.ndarray:
        return np.array(mi.render(mi.load_dict(mitsuba_dict(data, mi, centres=True, **kind))))

    lights = [picture(only_light=i)[..., :3] for i in range(len(data.get("lights", [])))]
    return {"depth": picture(depth=True)[..., 0], "lights": np.array(lights)}


HASWELL_FEATURES = b"+avx,+avx2,+bmi,+bmi2,+cx16,+f16c,+fma,+lzcnt,+movbe,+popcnt,+sse4.2"


def drjit_target(cpu: str) -> str:
    """Dr.Jit's LLVM target, set first for ``cpu``: "haswell" is AVX2 and 8 lanes (the native
    target on an AVX-512 machine has 16). Dr.Jit's Python API has no call for it; its core
    library's ``jit_llvm_set_target`` does (C++ linkage, so by its mangled name), and takes
    effect once the LLVM backend has started, for every kernel compiled after it."""
    import ctypes

    import drjit as dr

    dr.eval(dr.llvm.Float([0.0]))  # starts the LLVM backend
    core = ctypes.CDLL(str(Path(dr.__file__).with_name("libdrjit-core.so")))
    if cpu == "haswell":
        set_target = core._Z19jit_llvm_set_targetPKcS0_j
        set_target.argtypes = [ctypes.c_char_p, ctypes.c_char_p, ctypes.c_uint32]
        set_target(b"haswell", HASWELL_FEATURES, 8)
    target_cpu, lanes = core._Z19jit_llvm_target_cpuv, core._Z21jit_llvm_vector_widthv
    target_cpu.restype, lanes.restype = ctypes.c_char_p, ctypes.c_uint32
    return f"{target_cpu().decode()}, {lanes()} lanes"


# Mitsuba's BVH walk is Embree's, compiled ahead for every instruction set and picked by the
# processor it finds; Mitsuba makes Embree's device with a fixed configuration, and Embree
# reads no file or variable, so the haswell run puts "isa=avx2" into that configuration with
# this library, preloaded in Mitsuba's child (LD_PRELOAD)
EMBREE_SHIM = r"""
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
typedef void *(*new_device)(const char *);
void *_ZN7mitsuba12rtcNewDeviceEPKc(const char *config) {
    void *embree = dlopen(getenv("RAYKIT_EMBREE_LIBRARY"), RTLD_NOW | RTLD_NOLOAD);
    new_device real = embree ? (new_device) dlsym(embree, "_ZN7mitsuba12rtcNewDeviceEPKc") : 0;
    if (!real) { fprintf(stderr, "embree shim: %s\n", dlerror()); abort(); }
    char joined[1024];
    snprintf(joined, sizeof joined, "%s,%s", config, getenv("RAYKIT_EMBREE_CONFIG"));
    return real(joined);
}
"""


def embree_avx2(folder: Path) -> dict | None:
    """The environment that restricts a Mitsuba child's Embree to AVX2 (:data:`EMBREE_SHIM`,
    compiled into ``folder`` with the C compiler), or None without a compiler or Mitsuba."""
    import shutil

    try:
        import mitsuba
    except ImportError:
        return None
    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        return None
    source, shim = folder / "embree_shim.c", folder / "embree_shim.so"
    source.write_text(EMBREE_SHIM)
    made = subprocess.run([compiler, "-shared", "-fPIC", "-O2", "-o", shim, source, "-ldl"])
    if made.returncode != 0:
        return None
    library = Path(mitsuba.__file__).with_name("libembree3.so")
    return {
        "LD_PRELOAD": str(shim),
        "RAYKIT_EMBREE_LIBRARY": str(library),
        "RAYKIT_EMBREE_CONFIG": "isa=avx2",
    }


CHILD_SECONDS = 600  # for one answer of a Mitsuba child: a child slower than that has hung
STILL_SECONDS = 0.002  # a child whose threads ran for none of this long is still
SETTLE_SECONDS = 1.0  # the longest wait for a child to be still after its render


class MitsubaChild:
    """One Mitsuba variant in a child process of its own (a variant that aborts takes only
    its child with it), set up on ``data`` (:func:`mitsuba_child`) for ``cpu``, with ``env``
    added to its environment (and ``threads``, its thread pool's size, when given): ``load``,
    ``first``, ``hit``, ``target`` (Dr.Jit's), and
    :meth:`render_once`. ``failure``: a one-line message, once the child has
    failed to start, died, answered nonsense or taken longer than CHILD_SECONDS for an
    answer; it is then killed, and its row gives the message. ``script``: the benchmark whose
    ``--child VARIANT --cpu CPU`` runs the child (:func:`mitsuba_child`, this one's, by
    default); its first answer is a JSON object, whose fields this one's reads when present."""

    def __init__(
        self,
        variant: str,
        data: dict,
        cpu: str = "native",
        env: dict | None = None,
        script: str = __file__,
        threads: int | None = None,
    ):
        env = {**os.environ, **(env or {})}
        if variant.startswith("llvm") and Path(LLVM_19).exists():
            env.setdefault("DRJIT_LIBLLVM_PATH", LLVM_19)
        self.errors = tempfile.TemporaryFile(mode="w+")
        self.process = subprocess.Popen(
            [sys.executable, script, "--child", variant, "--cpu", cpu]
            + (["--threads", str(threads)] if threads else []),
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self.errors,
            text=True,
            env=env,
        )
        self.failure = None
        self.made = self.ask(json.dumps(data), json.loads)
        if self.made is not None:
            self.load, self.first = self.made.get("load"), self.made.get("first")
            self.hit, self.target = self.made.get("hit"), self.made.get("target")

    def check(self) -> dict | None:
        """The child's pictures for :func:`agreement` (:func:`check_pictures`, and its first
        render as ``image``), or None once it has failed."""
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "check.npz"
            if self.failure is None and self.ask(f"check {path}", int) == 1:
                with np.load(path) as pictures:
                    return dict(pictures)
        return None

    def render_once(self) -> float:
        """Render once in the child: the seconds it took, by the child's clock (NaN once the
        child has failed); returns once the child is still (:meth:`settle`)."""
        took = self.ask("render", float) if self.failure is None else None
        self.settle()
        return float("nan") if took is None else took

    def settle(self) -> None:
        """Wait, SETTLE_SECONDS at most, until none of the child's threads has run for
        STILL_SECONDS. Dr.Jit's thread pool goes on running for some milliseconds after a
        render has returned, waiting for more work, on the cores the next renderer's render
        would take: timed then, a render of raykit's on all cores took up to twice its time.
        Where the threads' times cannot be read (no /proc), it returns at once."""
        ran = self._ran()
        waited = time.perf_counter()
        while ran is not None and time.perf_counter() - waited < SETTLE_SECONDS:
            time.sleep(STILL_SECONDS)
            ran, before = self._ran(), ran
            if ran == before:
                return

    def _ran(self) -> int | None:
        """Nanoseconds the child's threads have run so far (Linux's schedstat), or None."""
        total = None
        for stat in Path(f"/proc/{self.process.pid}/task").glob("*/schedstat"):
            try:
                total = (total or 0) + int(stat.read_text().split()[0])
            except (OSError, ValueError, IndexError):  # a thread that ended meanwhile
                continue
        return total

    def close(self) -> None:
        if self.failure is None:
            self.process.stdin.close()
            try:
                self.process.wait(timeout=60)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
            self.process.stdout.close()
            self.errors.close()

    def ask(self, request: str, read):
        """Send ``request`` as a line and read the answer's line with ``read``; None, with
        ``failure`` set and the child gone, if that fails."""
        try:
            self.process.stdin.write(request + "\n")
            self.process.stdin.flush()
            ready, _, _ = select.select([self.process.stdout], [], [], CHILD_SECONDS)
            if not ready:
                raise TimeoutError(f"no answer in {CHILD_SECONDS} s")
            return read(self.process.stdout.readline())
        except (OSError, ValueError) as error:  # a broken pipe, an empty line: it died
            self.failure = self._failed(error)
            return None

    def _failed(self, error: Exception) -> str:
        self.process.kill()
        returncode = self.process.wait()
        for stream in (self.process.stdin, self.process.stdout):
            try:
                stream.close()
            except OSError:  # the pipe to a dead child may not flush
                pass
        self.errors.seek(0)
        lines = self.errors.read().strip().splitlines()
        self.errors.close()
        if isinstance(error, TimeoutError):
            why = str(error)
        else:  # what the child said last, or how it ended
            why = lines[-1] if lines else f"exit status {returncode}"
        return f"failed: {why[:80]}"


def _engines(engine: str) -> list[str]:
    """The raykit engines to time: both for ``auto`` (compiled only where numba is installed)."""
    from raykit.engine.choice import compiled_available

    if engine == "auto":
        if compiled_available():
            return ["numpy", "compiled"]
        print(
            'numba is not installed (pip install "raykit[fast]"): the compiled engine is not'
            " timed.\n"
        )
        return ["numpy"]
    return [engine]


def plot(path: Path, rows: list[dict]) -> None:
    """The render medians as bars: a group per scene, a bar per renderer. ``rows``:
    ``{"scene", "renderer", "render"}`` (seconds, or None for a variant that failed)."""
    scenes = list(dict.fromkeys(row["scene"] for row in rows))
    renderers = list(dict.fromkeys(row["renderer"] for row in rows))
    times = {(row["scene"], row["renderer"]): row["render"] for row in rows}
    bar_plot(
        path,
        scenes,
        {r: [times.get((s, r)) for s in scenes] for r in renderers},
        "render time, median (ms, log scale)",
        "raykit against Mitsuba 3, 1 sample per pixel",
        log=True,
    )


CPUS = ("native", "haswell")
AVX2 = " (AVX2)"  # the haswell run's renderers, in the plot


def main() -> None:
    parser = arguments(__doc__, "small scenes")
    parser.add_argument("--plot", type=Path, help="write the render medians as bars here")
    parser.add_argument(
        "--cpu",
        nargs="+",
        choices=CPUS,
        default=["native"],
        help="instruction sets, a run for each: native (the default), haswell (AVX2)",
    )
    parser.add_argument(
        "--threads",
        type=int,
        nargs="+",
        help="threads of each renderer, a run for each count (default: one run, one a core)",
    )
    parser.add_argument("--pictures", type=Path, help="save the lit scenes' pictures here (PNG)")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--rows", type=Path, help=argparse.SUPPRESS)
    parser.add_argument(
        "--engine",
        choices=ENGINES,
        default="auto",
        help="raykit's engine: numpy, compiled, or auto: both side by side (default)",
    )
    if "--child" in sys.argv:  # one Mitsuba variant, for the parent (MitsubaChild)
        args = parser.parse_args()
        mitsuba_child(args.child, args.cpu[0], args.threads[0] if args.threads else None)
        return
    if "--rows" in sys.argv:  # one instruction set's run, for the parent (run_for)
        args = parser.parse_args()
        args.rows.write_text(json.dumps(run(args, args.cpu[0], args.threads[0])))
        return
    args = parse(parser)
    if args.pictures:
        args.pictures.mkdir(parents=True, exist_ok=True)
    counts = args.threads or [None]
    rows = [
        row
        for cpu in args.cpu
        for threads in counts
        for row in (run(args, cpu, threads) if cpu == "native" else run_for(cpu, args, threads))
    ]
    if len(counts) > 1:
        summary(rows)
    if args.plot:
        plot(args.plot, rows)


def run_for(cpu: str, args: argparse.Namespace, threads: int | None) -> list[dict]:
    """:func:`run` for ``cpu`` in a process of its own, since numba reads its target from the
    environment once, as it is imported: "haswell" is numba's AVX2 (its CPU name and that
    CPU's own features, not the host's, which it would otherwise add). Its tables go to
    standard output as they are printed; the plot's rows come back."""
    env = {**os.environ, **numba_cpu(cpu)}
    from raykit.engine.choice import compiled_available

    # the AVX2 run times raykit's compiled engine alone: numpy's own SIMD dispatch is as shipped
    engine = args.engine
    if cpu == "haswell" and engine == "auto" and compiled_available():
        engine = "compiled"
    command = [sys.executable, __file__, "--repeats", str(args.repeats), "--engine", engine]
    command += ["--quick"] * args.quick + ["--threads", str(threads)] * bool(threads)
    command += ["--pictures", str(args.pictures)] if args.pictures else []
    with tempfile.TemporaryDirectory() as folder:
        rows = Path(folder) / "rows.json"
        sys.stdout.flush()
        if subprocess.run([*command, "--cpu", cpu, "--rows", str(rows)], env=env).returncode:
            raise SystemExit(f"the {cpu} run failed")
        return json.loads(rows.read_text())


def run(args: argparse.Namespace, cpu: str, threads: int | None) -> list[dict]:
    """Both tables, flat and lit scenes, for one instruction set (``cpu``) and each renderer's
    ``threads`` (None: one a core); the plot's and the summary's rows."""
    title = "Native instruction set" if cpu == "native" else "AVX2 (haswell)"
    each = f", {_threads(threads)} each" if threads else ""
    print(f"## {title}{each}\n")
    print(machine_line(cpu, threads) + "\n")
    if args.engine != "numpy":
        from raykit.engine.choice import compiled_available

        if compiled_available():
            import numba

            numba.set_num_threads(threads or numba.config.NUMBA_NUM_THREADS)
    try:
        import mitsuba

        version = mitsuba.__version__
    except ImportError:
        print("Mitsuba 3 is not installed (pip install mitsuba): raykit alone is timed.\n")
        version = None
    engines = _engines(args.engine)
    with tempfile.TemporaryDirectory() as folder:
        env = embree_avx2(Path(folder)) if cpu == "haswell" and version else None
        if cpu == "haswell" and version and env is None:
            print("No C compiler: Mitsuba's Embree takes the widest instruction set it finds.\n")
        timing = Timing(args, version, engines, cpu, env, Path(folder), threads)
        flat = timing.table(benchmark_scenes(args.quick, Path(folder)))
        print(
            f"\nMedians of {args.repeats} renders after a warm-up, every renderer of a scene in"
            " turns (each timed render right after an untimed one of its own); Mitsuba's"
            " variants in child processes that time their own renders. raykit compiled:"
            " prepare is raykit.engine.compiled.prepare (arrays, screen tiles, BVH for lit"
            " scenes), made once per scene as Mitsuba builds its BVH in load_dict; render"
            " renders the prepared scene. raykit.render.render(scene) does both; the numpy"
            " engine prepares inside its render.\n"
        )
        for name, (cold, ratio) in timing.cold.items():
            print(
                f"{name}, raykit compiled with its cache of decoded textures empty: prepare"
                f" {seconds(cold, 1)}, load + prepare + render / Mitsuba llvm"
                f" {f'{ratio:.2f}' if ratio else '-'} (median of {COLD_PREPARES} prepares).\n"
            )
        lit_rows = timing.table(lit_scenes(args.quick), lit=True)
    print(
        "\nLit scenes: two point lights, shadows, diffuse only, no ambient light; Mitsuba's"
        " direct integrator with one shadow ray per light per hit (emitter_samples 2,"
        " bsdf_samples 0). Timed as above. The pictures' check renders each pixel's centre"
        " with each light alone (untimed), brings Mitsuba's fall-off to raykit's"
        " (mitsuba_intensity) and compares linear colours over the pixels both hit."
        " Mitsuba llvm's lit render of many shapes has a cost per render that grows with the"
        " shapes, not the pixels (see the script's docstring): scalar_rgb is the better measure"
        " of its ray work there."
    )
    if timing.targets:
        print(f"Dr.Jit's LLVM backend compiled for: {'; '.join(sorted(timing.targets))}.")
    growth(timing.compiled_renders, args.repeats)
    rows = [{**row, "threads": threads} for row in flat + lit_rows]
    if len(args.threads or ()) > 1:  # the plot's bars of each count apart
        rows = [{**row, "renderer": f"{row['renderer']}, {_threads(threads)}"} for row in rows]
    if cpu == "native":
        return rows
    return [
        {**row, "renderer": row["renderer"] + AVX2}
        for row in rows
        if row["renderer"].startswith("raykit compiled") or "llvm_ad_rgb" in row["renderer"]
    ]


def summary(rows: list[dict]) -> None:
    """raykit compiled's ratios to Mitsuba llvm of every run, side by side: a row per scene
    (and instruction set), a column pair per thread count, render alone and load + prepare +
    render; and the cold-cache ratio of a textured scene where a run measured one. ``rows``: the
    runs' rows, with their ``threads`` and the ratios :meth:`Timing.scene_rows` gives raykit
    compiled's."""
    ours = [row for row in rows if "ratio" in row]
    if not ours:  # raykit's numpy engine alone: no compiled rows
        return
    counts = list(dict.fromkeys(row["threads"] for row in ours))
    scenes = list(dict.fromkeys((row["scene"], row["cpu"]) for row in ours))
    by = {(row["scene"], row["cpu"], row["threads"]): row for row in ours}
    print("\n## raykit compiled against Mitsuba llvm, every run\n")
    head = "".join(f" {_threads(n)}: render | load + prepare + render |" for n in counts)
    print(f"| scene | instruction set |{head}")
    print("|---|---|" + "---|---|" * len(counts))
    for scene, cpu in scenes:
        cells = ""
        for n in counts:
            row = by.get((scene, cpu, n), {})
            whole = row.get("whole_ratio") or "-"
            if row.get("cold_ratio"):
                whole += f" (textures not cached: {row['cold_ratio']})"
            cells += f" {row.get('ratio') or '-'} | {whole} |"
        print(f"| {scene} | {cpu} |{cells}")
    print(
        "\nEach ratio is raykit compiled's time over Mitsuba llvm's, from the run's own table"
        " above (threads: of each renderer)."
    )


def _threads(count: int) -> str:
    return f"{count} thread{'s' * (count > 1)}"


def machine_line(cpu: str, threads: int | None = None) -> str:
    """The processor, the instruction set this run's compiled code was made for, and the
    threads each renderer takes."""
    model, widest = processor()
    model, widest = model or "an unnamed processor", widest or "neither AVX2 nor AVX-512"
    if cpu == "native":
        how = (
            f"native: numba, Dr.Jit and Embree each compile for, or pick, the processor they find"
            f" ({widest})"
        )
    else:
        how = (
            "AVX2: numba for haswell (NUMBA_CPU_NAME=haswell, NUMBA_CPU_FEATURES empty: haswell's"
            " own), Dr.Jit's LLVM backend for haswell with 8 lanes (drjit_target), Mitsuba's"
            " Embree restricted to isa=avx2 (embree_avx2); numpy, and Mitsuba's other"
            " ahead-compiled code, are as shipped"
        )
    # the machine's other work as the run starts: every renderer is timed in turns with the
    # others, but a loaded machine slows the many-threaded ones most
    load = os.getloadavg()[0]
    each = (
        f"{threads} (raykit's numba threads, Mitsuba's Dr.Jit thread pool)"
        if threads
        else "one a core"
    )
    return (
        f"Machine: {model}, {os.cpu_count()} cores, {widest}; load average {load:.1f} as this"
        f" run started (1 minute). Instruction set of this run: {how}. Threads of each"
        f" renderer: {each}."
    )


class Timing:
    """Times every renderer of each scene in turns and prints a table; keeps what the growth
    line and the plot need (``compiled_renders``, rows) and Dr.Jit's targets."""

    def __init__(self, args, version: str | None, engines: list[str], cpu: str, env: dict | None,
                 folder: Path, threads: int | None):  # fmt: skip
        self.args, self.version, self.engines, self.cpu, self.env = args, version, engines, cpu, env
        self.threads = threads  # of each renderer (None: one a core)
        self.folder = folder  # where raykit's scene files are written (set_up_raykit)
        self.compiled_renders: dict = {}
        self.cold: dict = {}  # per textured scene: (prepare with no decoded textures, ratio)
        self.targets: set[str] = set()

    def table(self, scenes: dict[str, Scene], lit: bool = False) -> list[dict]:
        """One table, a row per scene and renderer; for ``lit`` scenes, with the pictures'
        agreement (:func:`agreement`). The plot's rows: ``{"scene", "renderer", "render"}``."""
        extra = " colours: mean abs. difference, pixels off by > 0.01 |" if lit else ""
        print(
            "| scene | renderer | load | prepare | first render | render (median) "
            "| load + prepare + render | render / Mitsuba llvm "
            f"| load + prepare + render / Mitsuba llvm | hit masks agree |{extra}"
        )
        print("|---|---|---|---|---|---|---|---|---|---|" + "---|" * lit)
        rows = []
        for name, scene in scenes.items():
            rows += self.scene_rows(name, scene, lit)
        return rows

    def scene_rows(self, name: str, scene: Scene, lit: bool) -> list[dict]:
        data = scene_data(scene)
        renderers, picture, children = {}, None, []
        blank = "-" + " | -" * lit
        for engine in self.engines:
            load, prepare, first, render_once, picture = set_up_raykit(engine, data, self.folder)
            renderers[f"raykit {engine}"] = (load, prepare, first, render_once, blank)
        if lit and self.args.pictures:
            save_image(picture[0], self.args.pictures / f"{_slug(name)}_raykit.png")
        ours = picture[1] >= 0  # the last engine's (all give the same picture)
        for variant in VARIANTS if self.version is not None else ():
            child = MitsubaChild(variant, data, self.cpu, self.env, threads=self.threads)
            renderer = f"Mitsuba {self.version} {variant}"
            check = child.check() if lit and child.failure is None else None
            if child.failure:
                renderers[renderer] = (child.failure, None, None, None, "")
                continue
            children.append((child, renderer))
            if child.target:
                self.targets.add(child.target)
            if lit:
                hits, mean, off, converted = agreement(scene, picture, check)
                agree = f"{hits:.1%} | {mean:.1e}, {off:.1%}"
                if self.args.pictures:
                    stem = self.args.pictures / f"{_slug(name)}_{variant}"
                    # Mitsuba's float32 quantized in float64, as raykit's pictures are (in
                    # float32, x * 255 + 0.5 rounds some colours to the other byte)
                    image = np.asarray(check["image"], np.float64)
                    save_image(image, stem.with_name(stem.name + ".png"))
                    save_image(converted, stem.with_name(stem.name + "_as_raykit.png"))
            else:
                agree = f"{np.mean(np.array(child.hit) == ours):.1%}"
            renderers[renderer] = (child.load, 0.0, child.first, child.render_once, agree)
        medians = medians_in_turns(
            {key: r[3] for key, r in renderers.items() if r[3] is not None},
            self.args.repeats,
            warm=True,
        )
        for child, renderer in children:
            child.close()
            if child.failure:  # it died, or hung, during the renders in turns
                renderers[renderer] = (child.failure, None, None, None, "")
                medians.pop(renderer)
        llvm = next((t for key, t in medians.items() if key.endswith("llvm_ad_rgb")), None)
        llvm_whole = next(
            (r[0] + medians[key] for key, r in renderers.items() if key.endswith("llvm_ad_rgb")),
            None,
        )  # Mitsuba's load (its BVH) and render
        rows = []
        for renderer, (load, prepare, first, render_once, agree) in renderers.items():
            took = medians.get(renderer)
            row = {"scene": name, "renderer": renderer, "render": took, "cpu": self.cpu}
            rows.append(row)
            if isinstance(load, str):
                print(f"| {name} | {renderer} | {load} | | | | | | | |" + " |" * lit)
                continue
            whole = load + prepare + took
            ratio = f"{took / llvm:.2f}" if llvm else "-"
            whole_ratio = f"{whole / llvm_whole:.2f}" if llvm_whole else "-"
            if renderer == "raykit compiled":
                self.compiled_renders[name] = (load + prepare, took, render_once)
                row.update(ratio=ratio, whole_ratio=whole_ratio)
                if any(board.texture for board in scene.billboards):
                    cold = cold_prepare(self.folder / "scene.json")  # this scene's file
                    whole_cold = (load + cold + took) / llvm_whole if llvm_whole else None
                    self.cold[name] = (cold, whole_cold)
                    row["cold_ratio"] = f"{whole_cold:.2f}" if whole_cold else None
            print(
                f"| {name} | {renderer} | {seconds(load, 1)} "
                f"| {seconds(prepare, 1) if prepare else '-'} | {seconds(first, 1)} "
                f"| {seconds(took, 1)} | {seconds(whole, 1)} | {ratio} | {whole_ratio} | {agree} |"
            )
        return rows


def agreement(scene: Scene, picture: tuple, check: dict) -> tuple:
    """How near Mitsuba's lit picture is to raykit's ``picture`` (rgb, object index, t):
    ``(hits, mean, off, converted)``, the share of pixels on which both agree whether anything
    is hit, the mean absolute difference of linear colours (over the channels of the pixels both
    hit), the share of those pixels off by more than 0.01 in a channel, and Mitsuba's picture as
    raykit's radiometry would make it ``(H, W, 3)``. ``check``: :func:`check_pictures`, every
    pixel sampled at its centre as raykit's. Each light's picture is multiplied by (r/r0)²
    (:func:`mitsuba_intensity`), r the distance from the light to raykit's hit point."""
    rgb, index, t = picture
    ours, theirs = index >= 0, check["depth"] > 0
    both = ours & theirs
    rows, cols = np.nonzero(both)
    origins, directions = rays_through(scene.camera, cols + 0.5, rows + 0.5)
    points = origins + t[both][:, None] * directions
    converted = np.zeros(rgb.shape)
    for light, alone in zip(scene.lights, check["lights"], strict=True):
        to_light = np.asarray(light.position) - points
        r0 = _distance2(light.position, scene.camera.lookat)
        converted[both] += alone[both] * (dot(to_light, to_light) / r0)[:, None]
    difference = np.abs(rgb[both] - converted[both])
    off = np.mean(difference.max(axis=1) > 0.01) if len(difference) else 0.0
    return np.mean(ours == theirs), float(difference.mean()), off, converted


def _slug(name: str) -> str:
    return "_".join(name.replace(",", "").split())


def set_up_raykit(engine: str, data: dict, folder: Path) -> tuple:
    """raykit on one scene from its file: ``(load, prepare, first render, render_once,
    picture)``, times in seconds; ``render_once()`` renders once more and returns the seconds
    it took; ``picture``: the first render's ``(rgb, object_index, t)``. ``data`` is written as
    a scene file in ``folder`` (textures by their paths), and load is the median of 3
    :func:`~raykit.io.scene_json.load_scene` of it: reading the JSON, checking it, reading
    each texture's header. The compiled engine's first render is a whole ``render(scene)`` (it
    loads the cached kernels, as Mitsuba's first render compiles its own); then it renders the
    prepared scene, whose ``prepare`` is the median of 3, each of a scene just loaded, so that
    it decodes the textures as a first use does. The numpy engine prepares inside its render
    (prepare 0)."""
    path = folder / "scene.json"
    path.write_text(json.dumps(data))
    loaded, load = median_time(lambda: load_scene(path), 3)

    if engine != "compiled":
        start = time.perf_counter()
        first = render(loaded, engine=engine)
        took = time.perf_counter() - start
        call = timer(lambda: render(loaded, engine=engine, hits=False))
        return load, 0.0, took, call, (first.rgb, first.object_index, first.t)
    from raykit.engine import compiled

    start = time.perf_counter()
    compiled.render.render(loaded, hits=False)
    first = time.perf_counter() - start
    preparing = []
    for _ in range(3):
        fresh = load_scene(path)
        start = time.perf_counter()
        prepared = compiled.prepare(fresh)
        preparing.append(time.perf_counter() - start)
    prepare = statistics.median(preparing)
    picture = compiled.render.render(prepared)  # untimed: the hits too, for agreement
    render_once = timer(lambda: compiled.render.render(prepared, hits=False))
    return load, prepare, first, render_once, picture


COLD_PREPARES = 9  # a prepare of a few textures takes milliseconds: a median of 3 moved by half


def cold_prepare(path: Path) -> float:
    """The median of COLD_PREPARES ``raykit.engine.compiled.prepare`` of the scene file at
    ``path``, each just loaded with raykit's cache of decoded textures empty (a new folder each
    time), so each of its textures is decoded."""
    from raykit.engine import compiled

    took = []
    cache = os.environ.get("RAYKIT_CACHE_DIR")
    try:
        for _ in range(COLD_PREPARES):
            with tempfile.TemporaryDirectory() as empty:
                os.environ["RAYKIT_CACHE_DIR"] = empty  # read by each decode
                fresh = load_scene(path)
                start = time.perf_counter()
                compiled.prepare(fresh)
                took.append(time.perf_counter() - start)
    finally:
        os.environ.pop("RAYKIT_CACHE_DIR", None)
        if cache is not None:
            os.environ["RAYKIT_CACHE_DIR"] = cache
    return statistics.median(took)


def growth(compiled_renders: dict, repeats: int) -> None:
    """The issue's growth goals for the compiled engine: sphereflake 4 to 6 (81x the spheres)
    at most 3x the render time, and level 6 loaded, prepared and rendered within 2 s (from its
    row). ``compiled_renders``: per scene, (load + prepare, render median, the table's timer of
    one render of the prepared scene). The render ratio is timed here with the table's two
    timers in turns, 3 x ``repeats`` rounds, each timed render right after an untimed one of
    the same scene (:func:`common.medians_in_turns`): in three runs of the table at commit 1bd1483,
    sphereflake 4's median alone, and with it the ratio of the rows, moved widely as the
    machine's other work came and went."""
    names = {
        level: next(
            (name for name in compiled_renders if name.startswith(f"sphereflake {level}")), None
        )
        for level in (4, 6)
    }
    if None in names.values():
        return
    timers = {level: compiled_renders[name][2] for level, name in names.items()}
    medians = medians_in_turns(timers, 3 * repeats, warm=True)
    level6_loaded = compiled_renders[names[6]]
    print(
        f"\nGrowth, raykit compiled: sphereflake 6 renders in {medians[6] / medians[4]:.2f}x the "
        f"time of sphereflake 4 ({seconds(medians[6], 1)} against {seconds(medians[4], 1)}, "
        f"medians of {3 * repeats} renders of each in turns, each after one untimed; goal: 3x "
        f"or less); level 6 loads, "
        f"prepares and renders in {level6_loaded[0] + level6_loaded[1]:.2f} s (goal: 2 s or less)."
    )


if __name__ == "__main__":
    main()

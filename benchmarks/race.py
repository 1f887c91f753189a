"""Time against error, raykit against Mitsuba 3 on the same pictures: for each effect of
distributed ray tracing both renderers model alike, how long each takes to reach each RMS error.

    python benchmarks/race.py [--quick] [--repeats N] [--sizes 80x60 640x480] [--threads 1 2]
        [--reference SPP] [--most SPP] [--cache FOLDER] [--plot docs/benchmarks/race.png]
        [--page docs/benchmarks/race.md]

The effects, each a scene made from an example scene, in raykit's format and converted for
Mitsuba (:func:`mitsuba_compare.mitsuba_dict`, :func:`sampling_error.mitsuba_scene`):

* antialiasing: ``scenes/classic.json`` in flat colours (each textured billboard a colour of its
  own), every object an area emitter of its colour seen directly in Mitsuba (``path``
  integrator, ``max_depth`` 1, the background a ``constant`` emitter): only the point in the
  pixel varies;
* soft shadows: ``scenes/soft_shadows.json`` made diffuse (no highlight, no ambient light), its
  panel a *physically based* area light (:func:`raykit.lights.area_intensity`) of the radiance
  that matches the FOCG light it replaces at the camera's lookat point
  (:func:`mitsuba_compare.mitsuba_radiance`); in Mitsuba a ``rectangle`` with an ``area``
  emitter of that radiance, ``diffuse`` BSDFs and the ``direct`` integrator, one emitter sample
  and no BSDF sample a sample, as raykit takes one point of the light a sample;
* depth of field: ``scenes/depth_of_field.json`` in flat colours through its thin lens
  (Mitsuba's ``thinlens`` sensor, aperture_radius = raykit's aperture / 2), seen as
  antialiasing's.

Glossy reflection (FOCG's perturbation in a square) and motion blur (Mitsuba 3 moves no shape
during the shutter) are not shared, and not raced (benchmarks/sampling_error.py measures them).

The same picture first. For each effect and size, raykit's converged picture (``--reference``
samples per pixel, 4096 by default, of its Sobol' sampler) and Mitsuba's (as many of its
``stratified`` sampler, in renders of 1024 with seeds of their own, averaged) are compared: the
mean and the largest absolute difference of their linear colours. Where the mean is within
:data:`TOLERANCE`, their average is the common reference both renderers' errors are measured
against; where it is not, the effect is not raced and no ratio is printed. Both are cached in
``--cache`` (by default ``~/.cache/raykit/race``), keyed by the scene, the count, raykit's
sources and Mitsuba's version.

The race. Each renderer with each of its samplers (raykit's random, jittered and Sobol'; Mitsuba's
independent, stratified and ldsampler, its low-discrepancy one) renders at 1, 4, 16, ... samples per
pixel, up to the first count whose error is below the lowest level (a first untimed render at each
count finds it, and warms each renderer up: raykit's compiled kernels loaded, Dr.Jit's kernels
compiled), with one thread and with every core (``--threads``; raykit's numba threads, a Mitsuba
child of a Dr.Jit thread pool of that size each), all of an effect's renders in turns
(:func:`common.medians_in_turns`), over ``--repeats`` seeds: the RMS error over the pixels, channels
and seeds against the common reference, and the median time. Render alone: raykit's compiled
engine's render of a scene prepared before (``raykit.engine.compiled.prepare``; its sampling made
inside the time), of the picture alone (``hits=False``: no object index and t per pixel, so no
ray through each pixel's centre for them, as ``raykit render`` renders a PNG), Mitsuba's
``mi.render`` of a scene ``load_dict`` loaded before. Load + render:
that plus the median time of loading the scene from its file and making it ready (raykit:
``load_scene`` and ``prepare``; Mitsuba: ``load_dict``, which builds its BVH), each timed
``--repeats`` times in the same turns. The time to reach each error level of :data:`LEVELS` is read
off each curve's log-log line of error against time (interpolated between measured counts; a level
already reached at 1 sample per pixel takes that render's time, marked ≤), and the fastest sampler
of each renderer is compared: the ratio raykit / Mitsuba.

The goal (issue 57): every level of every effect in at most half Mitsuba's time, one thread and
every core, load included, at 640x480, and never more than its time at any level.
"""

from __future__ import annotations

import argparse
import hashlib
import itertools
import json
import os
import sys
import tempfile
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import (  # noqa: E402
    arguments,
    medians_in_turns,
    page_of_output,
    parse,
    processor,
    seconds,
)
from mitsuba_compare import (  # noqa: E402
    MitsubaChild,
    answer_stream,
    mitsuba_dict,
    mitsuba_radiance,
    rectangle,
)
from sampling_error import FLAT_GROUND, sources_digest  # noqa: E402

from raykit.io.scene_json import load_scene, scene_from_dict  # noqa: E402
from raykit.sampling import Sampling  # noqa: E402

SCENES = HERE.parent / "scenes"
PAGE = HERE.parent / "docs" / "benchmarks" / "race.md"
VARIANT = "llvm_ad_rgb"
RAYKIT_SAMPLERS = ("random", "jittered", "sobol")
MITSUBA_SAMPLERS = ("independent", "stratified", "ldsampler")
LEVELS = (0.03, 0.02, 0.01, 0.005, 0.003, 0.002)  # RMS errors, the range
TOLERANCE = 0.005  # the converged pictures' mean absolute difference, at most
REFERENCE_SEED = 1_000_000  # no measured render's seed (they count from 1)
MITSUBA_CHUNK = 1024  # samples per pixel of one of Mitsuba's reference renders
MOST_SPP = 4096
REPEATS = 3  # renders a point of a curve, by default (their median)
# antialiasing's billboards, each a colour of its own in place of its texture
BOARD_COLOURS = ([0.8, 0.3, 0.2], [0.2, 0.5, 0.8], [0.9, 0.8, 0.3], FLAT_GROUND)


@dataclass(frozen=True)
class Effect:
    """One effect's scene at one size, as raykit's JSON ``data``, and where it came from."""

    name: str
    source: str
    data: dict

    @property
    def size(self) -> str:
        return f"{self.data['camera']['width']}x{self.data['camera']['height']}"


@dataclass
class Curve:
    """One renderer, sampler and thread count: per count of samples per pixel ``spp`` the
    squared errors of each seed's render and the median seconds, and the median seconds of a
    load (from the file to ready)."""

    renderer: str
    sampler: str
    threads: int
    spp: list[int]
    squared: dict[int, list[float]] = field(default_factory=dict)
    seconds: dict[int, float] = field(default_factory=dict)
    load: float = 0.0

    @property
    def label(self) -> str:
        return f"{self.renderer} {self.sampler}"

    def rmse(self) -> list[float]:
        return [float(np.sqrt(np.mean(self.squared[n]))) for n in self.spp]

    def times(self, load: bool = False) -> list[float]:
        return [self.seconds[n] + (self.load if load else 0.0) for n in self.spp]


def _json(name: str) -> dict:
    data = json.loads((SCENES / name).read_text())
    data.pop("$schema", None)
    return data


def effects(width: int, height: int) -> list[Effect]:
    """The raced effects' scenes at ``width`` x ``height`` (see the module page)."""
    classic = _json("classic.json")
    for board, colour in zip(classic["billboards"], itertools.cycle(BOARD_COLOURS)):
        board.pop("image", None), board.setdefault("color", colour)
    soft = _json("soft_shadows.json")
    soft.pop("ambient")
    for sphere in soft["spheres"]:
        sphere.pop("specular", None), sphere.pop("shininess", None)
    light = soft["lights"][0]
    radiance = mitsuba_radiance(light, soft["camera"])
    soft["lights"] = [
        {key: value for key, value in light.items() if key != "color"}
        | {"radiance": [round(float(x), 4) for x in radiance]}
    ]
    focus = _json("depth_of_field.json")
    focus.pop("ambient"), focus.pop("lights")
    for board in focus["billboards"]:
        board.pop("image"), board.setdefault("color", FLAT_GROUND)
    made = [
        ("antialiasing", "scenes/classic.json, flat colours", classic),
        ("soft shadows", "scenes/soft_shadows.json, diffuse, physically based light", soft),
        ("depth of field", "scenes/depth_of_field.json, flat colours", focus),
    ]
    out = []
    for name, source, data in made:
        data = {key: value for key, value in data.items() if key != "render"}
        data["version"] = 2
        data["camera"] = {**data["camera"], "width": width, "height": height}
        out.append(Effect(name, source, data))
    return out


def loaded(effect: Effect, folder: Path):
    """The effect's scene file in ``folder``, and the scene loaded from it."""
    path = folder / f"{effect.name.replace(' ', '_')}_{effect.size}.json"
    path.write_text(json.dumps(effect.data))
    return path, load_scene(path)


def _key(effect: Effect, *parts) -> str:
    text = json.dumps([effect.data, *parts], sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def raykit_reference(effect: Effect, spp: int, cache: Path) -> np.ndarray:
    """raykit's converged picture ``(H, W, 3)``: ``spp`` Sobol' samples per pixel, seed
    :data:`REFERENCE_SEED`, with every core; from ``cache`` when made there before."""
    import numba

    from raykit.engine import compiled

    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)

    path = cache / f"raykit-{_key(effect, spp, REFERENCE_SEED, sources_digest())}.npy"
    if path.exists():
        return np.load(path)
    scene = scene_from_dict(effect.data, effect.source, SCENES)
    sampled = replace(scene, sampling=Sampling(spp, "sobol", REFERENCE_SEED))
    image = compiled.render.render(sampled)[0]
    cache.mkdir(parents=True, exist_ok=True)
    np.save(path, image)
    return image


def mitsuba_reference(effect: Effect, spp: int, child, cache: Path, version: str):
    """Mitsuba's converged picture ``(H, W, 3)``: the mean of ``spp`` / MITSUBA_CHUNK renders of
    its stratified sampler, each MITSUBA_CHUNK samples per pixel with a seed of its own; from
    ``cache`` when made there before; None once the child has failed."""
    path = cache / f"mitsuba-{_key(effect, spp, REFERENCE_SEED, version)}.npy"
    if path.exists():
        return np.load(path)
    chunks = max(1, spp // MITSUBA_CHUNK)
    total = None
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "image.npy"
        for chunk in range(chunks):
            spp_here = min(spp, MITSUBA_CHUNK)
            request = f"render stratified {spp_here} {REFERENCE_SEED + chunk} {out}"
            if child.ask(request, float) is None:
                return None
            image = np.load(out).astype(np.float64)
            total = image if total is None else total + image
    image = total / chunks
    cache.mkdir(parents=True, exist_ok=True)
    np.save(path, image)
    return image


def raykit_timers(effect: Effect, scene, path: Path, curve: Curve, truth: np.ndarray):
    """A timer of one render (:func:`common.medians_in_turns`) per count of ``curve``, each
    rendering with the next seed (1, 2, ...) on ``curve.threads`` numba threads and keeping its
    squared error against ``truth`` in ``curve``; and one of a load: the scene file read and
    made ready (its sampling included)."""
    import numba

    from raykit.engine import compiled

    prepared = {
        n: compiled.prepare(replace(scene, sampling=Sampling(n, curve.sampler, 0)))
        for n in curve.spp
    }

    def render_at(n: int):
        seeds = itertools.count(1)

        def timed() -> float:
            numba.set_num_threads(curve.threads)
            sampled = replace(scene, sampling=Sampling(n, curve.sampler, next(seeds)))
            start = time.perf_counter()  # the seed's own sampling (at 1 sample a pixel,
            noise = compiled.scene_noise(sampled) if sampled.distributed else None  # none)
            image = compiled.render.render(prepared[n]._replace(scene=sampled, noise=noise),
                                           hits=False)[0]  # fmt: skip
            took = time.perf_counter() - start
            curve.squared[n].append(float(np.mean((image - truth) ** 2)))
            return took

        return timed

    def load() -> float:
        numba.set_num_threads(curve.threads)
        start = time.perf_counter()
        again = load_scene(path)
        compiled.prepare(replace(again, sampling=Sampling(curve.spp[0], curve.sampler, 1)))
        return time.perf_counter() - start

    return {n: render_at(n) for n in curve.spp}, load


def mitsuba_timers(child, curve: Curve, truth: np.ndarray, folder: Path):
    """As :func:`raykit_timers`, for renders and loads in the Mitsuba ``child`` (of
    ``curve.threads`` threads), timed by its own clock."""

    def render_at(n: int):
        seeds = itertools.count(1)

        def timed() -> float:
            out = folder / f"image-{curve.threads}.npy"
            took = child.ask(f"render {curve.sampler} {n} {next(seeds)} {out}", float)
            if took is None:
                return float("nan")
            curve.squared[n].append(float(np.mean((np.load(out) - truth) ** 2)))
            return took

        return timed

    def load() -> float:
        took = child.ask(f"load {curve.sampler}", float)
        return float("nan") if took is None else took

    return {n: render_at(n) for n in curve.spp}, load


def counts_reaching(render_once, lowest: float, most: int) -> list[int]:
    """The counts 1, 4, 16, ... up to the first whose render's error (``render_once(n)``, an
    untimed render, which also warms the renderer up) is below ``lowest``, or ``most``."""
    counts = [1]
    while True:
        error = render_once(counts[-1])
        if error is None or error < lowest or counts[-1] >= most:
            return counts
        counts.append(counts[-1] * 4)


def time_to(curve: Curve, level: float, load: bool = False) -> tuple[float, bool] | None:
    """The seconds ``curve`` takes to reach RMS error ``level`` (with its load, if ``load``),
    interpolated linearly in log error against log time between its two measured counts either
    side of it, and whether the level was reached at its first count already (its time then);
    None when no measured count reaches it."""
    errors, times = curve.rmse(), curve.times(load)
    if not errors:
        return None
    if errors[0] <= level:
        return times[0], True
    for (e0, t0), (e1, t1) in itertools.pairwise(zip(errors, times, strict=True)):
        if e1 <= level <= e0:
            share = 0.0 if e0 == e1 else (np.log(e0) - np.log(level)) / (np.log(e0) - np.log(e1))
            return float(np.exp(np.log(t0) + share * (np.log(t1) - np.log(t0)))), False
    return None


def fastest(curves: list[Curve], renderer: str, level: float, load: bool) -> float | None:
    """The least time any of ``renderer``'s curves takes to ``level``."""
    found = [time_to(c, level, load) for c in curves if c.renderer == renderer]
    found = [t for t, _ in filter(None, found)]
    return min(found) if found else None


def race(effect: Effect, args, child_of, folder: Path, version: str) -> dict | None:
    """Race one effect at one size (see the module page): print its agreement, its errors and
    its times to each level; the curves (None if not raced)."""
    print(f"## {effect.name}, {effect.size}\n\n{effect.source}.\n")
    path, scene = loaded(effect, folder)
    ours = raykit_reference(effect, args.reference, args.cache)
    children = {threads: child_of(effect, threads) for threads in args.threads}
    if any(c.failure for c in children.values()):
        failure = next(c.failure for c in children.values() if c.failure)
        print(f"Mitsuba {version} {VARIANT} {failure}: not raced.\n")
        return None
    theirs = mitsuba_reference(effect, args.reference, children[max(args.threads)], args.cache,
                               version)  # fmt: skip
    if theirs is None:
        print(f"Mitsuba {version} {VARIANT} failed: not raced.\n")
        return None
    difference = np.abs(ours - theirs)
    mean, largest = float(difference.mean()), float(difference.max())
    agree = mean <= TOLERANCE
    print(
        f"The converged pictures: raykit's ({args.reference} Sobol' samples per pixel) against"
        f" Mitsuba's ({args.reference} stratified samples per pixel): mean absolute difference"
        f" {mean:.1e}, largest {largest:.1e} (mean brightness {ours.mean():.4f} and"
        f" {theirs.mean():.4f}). "
        + (
            f"Within {TOLERANCE}: the same picture; errors below are against their mean."
            if agree
            else f"More than {TOLERANCE}: not the same picture, no race, no ratio."
        )
        + "\n"
    )
    if not agree:
        return None
    truth = (ours + theirs) / 2
    # the two references' noise is independent: the RMS of their difference is twice the
    # common reference's own noise, which every error below holds (in quadrature); an error
    # level below it is not measured, and gets no ratio
    floor = float(np.sqrt(np.mean((ours - theirs) ** 2)))
    print(
        f"The common reference's own noise, estimated as half the RMS difference of the two:"
        f" {floor / 2:.1e}; error levels below {floor:.1e} get no ratio.\n"
    )
    curves, timers = [], {}
    counts = {}  # per renderer and sampler: one calibration serves every thread count
    lowest, most_threads = min(LEVELS), max(args.threads)
    for sampler in RAYKIT_SAMPLERS:

        def once(n, sampler=sampler):
            from raykit.engine import compiled

            image = compiled.render.render(replace(scene, sampling=Sampling(n, sampler, 0)))[0]
            return float(np.sqrt(np.mean((image - truth) ** 2)))

        counts["raykit", sampler] = counts_reaching(once, lowest, args.most)
    for sampler in MITSUBA_SAMPLERS:

        def once(n, sampler=sampler, child=children[most_threads]):
            out = folder / "warm.npy"
            if child.ask(f"render {sampler} {n} 0 {out}", float) is None:
                return None
            return float(np.sqrt(np.mean((np.load(out) - truth) ** 2)))

        counts["Mitsuba", sampler] = counts_reaching(once, lowest, args.most)
        for threads, child in children.items():  # Dr.Jit's kernels compiled in each child
            if threads != most_threads:
                for n in counts["Mitsuba", sampler]:
                    child.ask(f"render {sampler} {n} 0 {folder / 'warm.npy'}", float)
    for threads in args.threads:
        for renderer, samplers in (("raykit", RAYKIT_SAMPLERS), ("Mitsuba", MITSUBA_SAMPLERS)):
            for sampler in samplers:
                curve = Curve(renderer, sampler, threads, list(counts[renderer, sampler]))
                curve.squared = {n: [] for n in curve.spp}
                if renderer == "raykit":
                    renders, load = raykit_timers(effect, scene, path, curve, truth)
                else:
                    renders, load = mitsuba_timers(children[threads], curve, truth, folder)
                curves.append(curve)
                timers |= {(curve.label, threads, n): timer for n, timer in renders.items()}
                timers[curve.label, threads, "load"] = load
    medians = medians_in_turns(timers, args.repeats)
    failed = [t for t, c in children.items() if c.failure]
    for child in children.values():
        child.close()
    if failed:
        print(f"Mitsuba {version} {VARIANT} failed during the race: no ratio.\n")
        return None
    for curve in curves:
        curve.seconds = {n: medians[curve.label, curve.threads, n] for n in curve.spp}
        curve.load = medians[curve.label, curve.threads, "load"]
    print_errors(curves, args.repeats)
    print_times(curves, args.threads, floor)
    return {"effect": effect, "curves": curves, "floor": floor}


def print_errors(curves: list[Curve], repeats: int) -> None:
    """Each curve's RMS error and median render time at each count it measured (one thread's
    errors are every thread count's: the same seeds)."""
    counts = sorted({n for c in curves for n in c.spp})
    print(
        f"RMS error against the common reference over {repeats} seeds, and the median render"
        " time (render alone), at each count of samples per pixel measured:\n"
    )
    print("| renderer | sampler | threads | " + " | ".join(f"{n} spp" for n in counts) + " |")
    print("|---|---|---|" + "---|" * len(counts))
    for curve in curves:
        cells = [
            f"{curve.rmse()[curve.spp.index(n)]:.4f}, {seconds(curve.seconds[n], 1)}"
            if n in curve.spp else ""
            for n in counts
        ]  # fmt: skip
        print(f"| {curve.renderer} | {curve.sampler} | {curve.threads} | {' | '.join(cells)} |")
    loads = ", ".join(
        f"{c.label}, {c.threads} thread(s): {seconds(c.load, 1)}"
        for c in curves
        if c.sampler in ("sobol", "ldsampler")
    )
    print(f"\nLoad (from the file to ready), medians: {loads}.\n")


def print_times(curves: list[Curve], threads_list: list[int], floor: float = 0.0) -> list[float]:
    """The time to each level, per curve, and the ratio of the fastest of each renderer, render
    alone and load + render, for each thread count (none at a level below ``floor``, the
    reference's own noise doubled); the ratios."""
    ratios = []
    labels = list(dict.fromkeys(c.label for c in curves))
    print(
        "Time to reach each RMS error (render alone; ≤: reached at 1 sample per pixel already,"
        " its time), and raykit's fastest sampler over Mitsuba's fastest, render alone and load"
        " + render:\n"
    )
    print("| RMS error | threads | " + " | ".join(labels) + " | raykit / Mitsuba | with load |")
    print("|---|---|" + "---|" * len(labels) + "---|---|")
    for threads in threads_list:
        mine = [c for c in curves if c.threads == threads]
        for level in LEVELS:
            cells = []
            for label in labels:
                found = time_to(next(c for c in mine if c.label == label), level)
                cells.append(
                    "not reached" if found is None
                    else ("≤ " if found[1] else "") + seconds(found[0], 1)
                )  # fmt: skip
            both = []
            for load in (False, True):
                r, m = (fastest(mine, who, level, load) for who in ("raykit", "Mitsuba"))
                unmeasured = r is None or m is None or level < floor
                both.append("-" if unmeasured else f"{r / m:.2f}")
                if load and not unmeasured:
                    ratios.append(r / m)
            print(f"| {level} | {threads} | {' | '.join(cells)} | {both[0]} | {both[1]} |")
    print()
    return ratios


def plot(path: Path, raced: list[dict], threads_list: list[int]) -> None:
    """RMS error against seconds (load + render), log-log, a line per renderer and sampler: a
    panel per effect (columns) and thread count (rows), of the largest size raced."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FormatStrFormatter, NullFormatter

    from raykit.io.images import save_figure

    largest = max(r["effect"].data["camera"]["width"] for r in raced)
    raced = [r for r in raced if r["effect"].data["camera"]["width"] == largest]
    rows, columns = len(threads_list), len(raced)
    figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.6 * rows + 0.8),
                                layout="constrained", squeeze=False)  # fmt: skip
    styles = {"random": "o-", "jittered": "s-", "sobol": "^-",
              "independent": "o--", "stratified": "s--", "ldsampler": "^--"}  # fmt: skip
    colours = {"raykit": ("C0", "C1", "C2"), "Mitsuba": ("C3", "C4", "C5")}
    legend = {}
    for row, threads in enumerate(threads_list):
        for column, result in enumerate(raced):
            ax = axes[row][column]
            for curve in (c for c in result["curves"] if c.threads == threads):
                samplers = RAYKIT_SAMPLERS if curve.renderer == "raykit" else MITSUBA_SAMPLERS
                colour = colours[curve.renderer][samplers.index(curve.sampler)]
                (line,) = ax.loglog(curve.times(load=True), curve.rmse(), styles[curve.sampler],
                                    color=colour, label=curve.label)  # fmt: skip
                legend.setdefault(curve.label, line)
            threads_text = "1 thread" if threads == 1 else f"{threads} threads"
            ax.set_title(f"{result['effect'].name}, {threads_text}", fontsize=11)
            ax.set_xlabel("seconds, load + render")
            ax.set_ylabel("RMS error")
            for axis in (ax.xaxis, ax.yaxis):
                axis.set_major_formatter(FormatStrFormatter("%g"))
                axis.set_minor_formatter(NullFormatter())
    size = raced[0]["effect"].size
    figure.suptitle(f"{size}: RMS error against seconds, load + render", fontsize=12)
    figure.legend(legend.values(), legend.keys(), loc="outside lower center", ncol=3)
    save_figure(figure, path)
    plt.close(figure)
    print(f"\nwrote {path}")


def mitsuba_scene(data: dict, mi, sampler: str) -> dict:
    """Mitsuba's scene for an effect's ``data`` (see the module page) with its ``sampler`` and a
    box filter: lit scenes as :func:`mitsuba_compare.mitsuba_dict` makes them (the ``direct``
    integrator, one emitter sample per sample); scenes without lights as emitters of their flat
    colours, seen directly."""
    scene = mitsuba_dict(data, mi)
    scene["sensor"]["sampler"] = {"type": sampler}
    if data.get("lights"):
        return scene
    scene["integrator"] = {"type": "path", "max_depth": 1}
    eye = data["camera"]["eye"]
    for i, b in enumerate(data["billboards"]):
        ul, ll, ur = (np.array(b[k], float) for k in ("upper_left", "lower_left", "upper_right"))
        scene[f"billboard{i}"] = rectangle(ul, ur - ul, ll - ul, mi, facing=eye)
    shapes = [(f"sphere{i}", s) for i, s in enumerate(data["spheres"])]
    shapes += [(f"billboard{i}", b) for i, b in enumerate(data["billboards"])]
    for key, shape in shapes:
        scene[key]["emitter"] = {
            "type": "area",
            "radiance": {"type": "rgb", "value": shape["color"]},
        }
    scene["background"] = {
        "type": "constant",
        "radiance": {"type": "rgb", "value": data["background"]},
    }
    return scene


def mitsuba_child(variant: str, threads: int | None) -> None:
    """In a child process (:class:`mitsuba_compare.MitsubaChild`): the effect's raykit data on
    the first line of standard input, loaded for each of :data:`MITSUBA_SAMPLERS`; prints
    ``{"load"}``; then for each line ``render SAMPLER SPP SEED PATH`` renders, saves the picture
    ``(H, W, 3)`` to PATH (.npy) and prints the seconds the render took; for ``load SAMPLER``,
    loads that sampler's scene again, prints the seconds, and lets it go."""
    answers = answer_stream()
    import drjit
    import mitsuba as mi

    mi.set_variant(variant)
    if threads:
        drjit.set_thread_count(threads)
    data = json.loads(sys.stdin.readline())
    start = time.perf_counter()
    scenes = {s: mi.load_dict(mitsuba_scene(data, mi, s)) for s in MITSUBA_SAMPLERS}
    took = (time.perf_counter() - start) / len(scenes)
    print(json.dumps({"load": took}), file=answers, flush=True)
    for line in sys.stdin:
        request = line.split()
        if request[0] == "render":
            sampler, spp, seed, path = request[1:]
            start = time.perf_counter()
            image = np.array(mi.render(scenes[sampler], spp=int(spp), seed=int(seed)))
            took = time.perf_counter() - start
            np.save(path, image[..., :3])
            print(took, file=answers, flush=True)
        elif request[0] == "load":  # a scene loaded and let go: the renders keep the first,
            start = time.perf_counter()  # whose kernels Dr.Jit has compiled (a new scene's
            mi.load_dict(mitsuba_scene(data, mi, request[1]))  # first render compiles them anew)
            print(time.perf_counter() - start, file=answers, flush=True)


def mitsuba_version() -> str | None:
    try:
        import mitsuba
    except ImportError:
        return None
    return mitsuba.__version__


def print_goal(raced: list[dict], threads_list: list[int]) -> None:
    """The goal's verdict at the largest size: each level of each effect, load included, for
    each thread count."""
    if not raced:
        return
    largest = max(r["effect"].data["camera"]["width"] for r in raced)
    ratios = []
    for result in raced:
        if result["effect"].data["camera"]["width"] != largest:
            continue
        for threads in threads_list:
            mine = [c for c in result["curves"] if c.threads == threads]
            for level in (x for x in LEVELS if x >= result["floor"]):
                r, m = (fastest(mine, who, level, True) for who in ("raykit", "Mitsuba"))
                if r is not None and m is not None:
                    ratios.append(r / m)
    if not ratios:
        return
    half = sum(r <= 0.5 for r in ratios)
    never = sum(r <= 1.0 for r in ratios)
    print(
        f"Goal at the largest size raced, load + render, every thread count: raykit's fastest"
        f" sampler in at most 0.5x Mitsuba {VARIANT}'s fastest at {half} of {len(ratios)}"
        f" levels, at most 1.0x at {never} of {len(ratios)}; ratios from {min(ratios):.2f} to"
        f" {max(ratios):.2f}."
    )


def machine_line(threads_list: list[int]) -> str:
    model, widest = processor()
    return (
        f"Machine: {model or 'an unnamed processor'}, {os.cpu_count()} cores"
        f"{', ' + widest if widest else ''}. Threads: {', '.join(map(str, threads_list))} (raykit's"
        f" numba threads; Mitsuba's Dr.Jit thread pool); load average"
        f" {os.getloadavg()[0]:.1f} as this run started (1 minute)."
    )


def main() -> None:
    parser = arguments(
        __doc__, "32x24 pictures, references of 256 samples per pixel, at most 64", REPEATS
    )
    parser.add_argument("--sizes", nargs="+", default=["80x60", "640x480"],
                        help="picture sizes, WIDTHxHEIGHT")  # fmt: skip
    parser.add_argument("--threads", nargs="+", type=int, default=None,
                        help="thread counts (default: 1 and every core)")  # fmt: skip
    parser.add_argument("--reference", type=int, default=MOST_SPP,
                        help="samples per pixel of each converged picture")  # fmt: skip
    parser.add_argument("--most", type=int, default=MOST_SPP,
                        help="samples per pixel a curve stops at, at most")  # fmt: skip
    parser.add_argument("--plot", type=Path, help="write the curves here (PNG)")
    parser.add_argument(
        "--cache",
        type=Path,
        default=Path.home() / ".cache" / "raykit" / "race",
        help="where the converged pictures are kept",
    )
    parser.add_argument("--page", type=Path, help=f"default (not with --quick): {PAGE}")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--cpu", default="native", help=argparse.SUPPRESS)
    if "--child" in sys.argv:  # Mitsuba in a child process, for the parent (MitsubaChild)
        child_args = parser.parse_args()
        mitsuba_child(child_args.child, child_args.threads[0] if child_args.threads else None)
        return
    args = parse(parser)
    if args.threads is None:
        args.threads = sorted({1, os.cpu_count() or 1})
    if args.quick:
        args.sizes, args.reference, args.most = ["32x24"], min(args.reference, 256), 64
    with page_of_output(args.page or (None if args.quick else PAGE)):
        run(args)


def run(args: argparse.Namespace) -> None:
    """Race every effect at every size (see the module page)."""
    print(machine_line(args.threads) + "\n")
    reduced = args.reference < MOST_SPP or args.most < MOST_SPP or args.repeats < REPEATS
    if reduced and not args.quick:
        print(
            f"A reduced run (the full race: --reference {MOST_SPP} --most {MOST_SPP} --repeats"
            f" {REPEATS}): converged pictures of {args.reference} samples per pixel, curves"
            f" stopped at {args.most}, {args.repeats} render(s) a point; a level below the"
            " references' own noise, or below the error a curve reaches at its last count, gets"
            " no ratio.\n"
        )
    version = mitsuba_version()
    if version is None:
        print("Mitsuba 3 is not installed (pip install mitsuba): nothing to race.")
        return

    def child_of(effect: Effect, threads: int) -> MitsubaChild:
        return MitsubaChild(VARIANT, effect.data, script=__file__, threads=threads)

    raced = []
    with tempfile.TemporaryDirectory() as folder:
        for size in args.sizes:
            width, height = (int(x) for x in size.split("x"))
            for effect in effects(width, height):
                result = race(effect, args, child_of, Path(folder), version)
                if result is not None:
                    raced.append(result)
    print_goal(raced, args.threads)
    print(f"\nLoad average as this run ended: {os.getloadavg()[0]:.1f} (1 minute).")
    if args.plot and raced:
        plot(args.plot, raced, args.threads)


if __name__ == "__main__":
    main()

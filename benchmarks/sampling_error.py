"""Error against samples for distributed ray tracing (FOCG 13.4): for each effect, the RMS
error against a converged reference versus samples per pixel and versus render time, for the
random, jittered and Sobol' samplers, and the slopes of the lines; the lecture's side of the
samplers. (The race against Mitsuba 3, on the same pictures, is benchmarks/race.py's.)

    python benchmarks/sampling_error.py [--quick] [--repeats N] [--engine auto]
        [--plot docs/benchmarks/sampling_error.png] [--cache FOLDER]
        [--page docs/benchmarks/sampling_error.md]

The effects, each a small scene (80x60; 32x24 with ``--quick``) made from an example scene:

* antialiasing: ``scenes/classic.json`` (flat colours: only the point in the pixel varies);
* soft shadows: ``scenes/soft_shadows.json`` made diffuse (no highlight, no ambient light), the
  panel its one area light (FOCG's);
* depth of field: ``scenes/depth_of_field.json`` in flat colours (no lights; the ground's
  checker texture a plain colour), through its thin lens;
* glossy reflection and motion blur: the first ``scenes/*glossy*.json`` and
  ``scenes/*motion*.json`` as they are, when raykit has them (a line says so when it has not).

For each sampler and samples per pixel spp = 1, 4, 16, 64, 256 (4^k, which jittered, n x n,
and Sobol', 2^m, both take; 1, 4, 16 with ``--quick``), ``--repeats`` renders, each with its
own seed: the RMS error against the reference (the root of the mean squared error over every
pixel, channel and seed) and the median render time: the compiled engine's scene is made ready
once, untimed, by ``raykit.engine.compiled.prepare`` (arrays, BVH, camera), and its time is that
of making the render's sampling (:func:`raykit.engine.compiled.scene_noise`) and rendering the
prepared scene, the image's assembly included; the numpy engine prepares nothing apart, and its
time is its whole ``raykit.render.render`` (``--engine auto`` by default). Every sampler and
count of an effect is rendered in turns (:func:`common.medians_in_turns`), so that the machine's
other work falls on all alike. At 1 sample per pixel the antialiasing scene, which has neither
area light nor lens, takes each pixel's centre whatever the sampler (:mod:`raykit.render`).

The reference is raykit's own render at 4,096 samples per pixel (256 with ``--quick``) with the
Sobol' sampler and a seed no measured render uses, cached in ``--cache`` (by default
``~/.cache/raykit/sampling_error``) under a key made of the scene, the count and raykit's
sources, so an edit of the renderer makes a new one. The slope of log RMSE against log spp is
fitted by least squares over spp >= 4 (the first count is the pixel centre for antialiasing,
and the asymptotic rate is what theory predicts), printed beside the theory's.
"""

from __future__ import annotations

import argparse
import hashlib
import itertools
import json
import math
import os
import sys
import time
from dataclasses import dataclass, replace
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

from raykit.engine.choice import ENGINES, choose, compiled_refuses  # noqa: E402
from raykit.io.errors import SceneError  # noqa: E402
from raykit.io.scene_json import scene_from_dict  # noqa: E402
from raykit.render import render  # noqa: E402
from raykit.sampling import SAMPLERS, Sampling  # noqa: E402
from raykit.scene import Scene  # noqa: E402

SCENES = HERE.parent / "scenes"
PAGE = HERE.parent / "docs" / "benchmarks" / "sampling_error.md"
REFERENCE_SEED = 1_000_000  # no measured render's seed (they count from 1)
FIT_FROM = 4  # the slope is fitted over spp >= this
FLAT_GROUND = [0.6, 0.6, 0.58]  # depth of field's ground, in place of its checker texture
# the slope of log RMSE against log spp, as the literature gives it for a pixel's 2D integral:
# independent samples -1/2 whatever the integrand; a stratified (jittered) set -3/4 where the
# integrand has an edge and -1 where it is smooth (Mitchell 1996, "Consequences of stratified
# sampling in graphics"); a scrambled Sobol' net -3/4 at edges (Pilleboue et al. 2015) and up to
# about -3/2 where smooth (Owen 1997)
THEORY = {
    "random": "-0.50",
    "jittered": "-0.75 (edges) to -1.00 (smooth)",
    "sobol": "-0.75 (edges) to about -1.50 (smooth)",
}


@dataclass(frozen=True)
class Effect:
    """One effect's scene, as raykit's JSON ``data`` and loaded, and where it came from."""

    name: str
    source: str
    data: dict
    scene: Scene


@dataclass
class Curve:
    """One sampler's measurements: per count of samples per pixel ``spp``, the squared errors
    of each seed's render, and the median seconds."""

    renderer: str
    sampler: str
    spp: list[int]
    squared: dict[int, list[float]]
    seconds: dict[int, float]

    @property
    def label(self) -> str:
        return f"{self.renderer} {self.sampler}"

    def rmse(self) -> list[float]:
        return [float(np.sqrt(np.mean(self.squared[n]))) for n in self.spp]

    def times(self) -> list[float]:
        return [self.seconds[n] for n in self.spp]


def _json(name: str) -> dict:
    return json.loads((SCENES / name).read_text())


def effects(width: int, height: int) -> tuple[list[Effect], list[str]]:
    """The effects' scenes at ``width`` x ``height``, and a line for each effect raykit lacks."""
    classic = _json("classic.json")
    soft = _json("soft_shadows.json")
    soft.pop("ambient")
    for sphere in soft["spheres"]:
        sphere.pop("specular", None), sphere.pop("shininess", None)
    focus = _json("depth_of_field.json")
    focus.pop("ambient"), focus.pop("lights")
    for board in focus["billboards"]:
        board.pop("image"), board.setdefault("color", FLAT_GROUND)
    made = [
        ("antialiasing", "scenes/classic.json", classic),
        ("soft shadows", "scenes/soft_shadows.json, diffuse, no ambient light", soft),
        ("depth of field", "scenes/depth_of_field.json, flat colours", focus),
    ]
    missing = []
    for name, pattern in (("glossy reflection", "*glossy*.json"), ("motion blur", "*motion*.json")):
        found = sorted(SCENES.glob(pattern))
        if not found:
            missing.append(f"{name}: raykit has no scene for it (scenes/{pattern}); not measured.")
            continue
        made.append((name, f"scenes/{found[0].name}", _json(found[0].name)))
    out = []
    for name, source, data in made:
        data = {**data, "camera": {**data["camera"], "width": width, "height": height}}
        # the samples are the benchmark's; the shutter stays the scene's (motion blur's own)
        shutter = data.get("render", {}).get("shutter")
        data = {key: value for key, value in data.items() if key != "render"}
        if shutter is not None:
            data["render"] = {"shutter": shutter}
        try:
            scene = scene_from_dict(data, source, SCENES)
        except SceneError as error:  # a format this raykit does not read yet
            missing.append(f"{name}: {error}; not measured.")
            continue
        out.append(Effect(name, source, data, scene))
    return out, missing


def sources_digest() -> str:
    """A digest of raykit's sources and the scenes' textures: a reference made by other code,
    or of other textures, is made anew."""
    digest = hashlib.sha256()
    for path in sorted([*(HERE.parent / "raykit").rglob("*.py"), *(SCENES / "textures").glob("*")]):
        digest.update(path.read_bytes())
    return digest.hexdigest()


def sampled(effect: Effect, spp: int, sampler: str, seed: int) -> Sampling:
    """The effect's scene's sampling with ``spp`` samples per pixel of ``sampler`` from
    ``seed``: its shutter kept (a moving scene blurs only while the shutter is open)."""
    return replace(effect.scene.sampling, samples_per_pixel=spp, sampler=sampler, seed=seed)


def reference(effect: Effect, spp: int, engine: str, cache: Path) -> np.ndarray:
    """raykit's converged picture ``(H, W, 3)`` of the effect: ``spp`` Sobol' samples per pixel,
    seed :data:`REFERENCE_SEED`, from ``cache`` when it was made there before."""
    key = json.dumps([effect.data, spp, REFERENCE_SEED, sources_digest()], sort_keys=True)
    path = cache / f"{hashlib.sha256(key.encode()).hexdigest()[:20]}.npy"
    if path.exists():
        return np.load(path)
    sampling = sampled(effect, spp, "sobol", REFERENCE_SEED)
    image = render(replace(effect.scene, sampling=sampling), engine=engine).rgb
    cache.mkdir(parents=True, exist_ok=True)
    np.save(path, image)
    return image


def raykit_timer(effect: Effect, curve: Curve, spp: int, engine: str, converged: np.ndarray):
    """A timer for :func:`common.medians_in_turns`: each call renders the effect at ``spp`` with
    the next seed (1, 2, ...), keeps its squared error in ``curve`` and returns its seconds: the
    numpy engine's whole render; the compiled engine's render of the scene prepared once,
    untimed, its sampling made anew for each seed inside the time (see the module page)."""
    seeds = itertools.count(1)
    renders_by = choose(
        engine, replace(effect.scene, sampling=sampled(effect, spp, curve.sampler, 1))
    )
    prepared = None
    if renders_by == "compiled":  # made ready once, as a renderer loads a scene once
        from raykit.engine import compiled

        prepared = compiled.prepare(
            replace(effect.scene, sampling=sampled(effect, spp, curve.sampler, 0))
        )

    def timed() -> float:
        sampling = sampled(effect, spp, curve.sampler, next(seeds))
        scene = replace(effect.scene, sampling=sampling)
        if prepared is None:
            start = time.perf_counter()
            image = render(scene, engine=renders_by).rgb
        else:  # the seed's own sampling (None: a scene without one, as prepare leaves it)
            start = time.perf_counter()
            noise = compiled.scene_noise(scene) if scene.distributed else None
            image = compiled.render.render(prepared._replace(scene=scene, noise=noise))[0]
        took = time.perf_counter() - start
        curve.squared[spp].append(float(np.mean((image - converged) ** 2)))
        return took

    return timed


def measure(effect: Effect, args, counts: list[int]) -> list[Curve]:
    """Every sampler's curve of the effect, against raykit's converged picture."""
    converged = reference(effect, args.reference, args.engine, args.cache)
    curves, timers = [], {}
    for sampler in SAMPLERS:
        curve = Curve("raykit", sampler, counts, {n: [] for n in counts}, {})
        # a first render, untimed: the compiled engine, if it renders, loads its kernels
        render(replace(effect.scene, sampling=sampled(effect, 1, sampler, 0)), engine=args.engine)
        for n in counts:
            timers[curve.label, n] = raykit_timer(effect, curve, n, args.engine, converged)
        curves.append(curve)
    medians = medians_in_turns(timers, args.repeats)
    for curve in curves:
        curve.seconds = {n: medians[curve.label, n] for n in counts}
    return curves


def slope(curve: Curve) -> float:
    """The least-squares slope of log RMSE against log spp, over spp >= :data:`FIT_FROM`."""
    pairs = [(n, e) for n, e in zip(curve.spp, curve.rmse(), strict=True) if n >= FIT_FROM]
    if len(pairs) < 2:
        return float("nan")
    x, y = np.log([p[0] for p in pairs]), np.log([p[1] for p in pairs])
    return float(np.polyfit(x, y, 1)[0])


def print_curves(effect: Effect, curves: list[Curve], engine: str, repeats: int) -> None:
    camera = effect.scene.camera
    print(f"## {effect.name}\n")
    print(
        f"{effect.source}, {camera.width}x{camera.height}; raykit's engine: {engine}; RMS "
        f"error over {repeats} seeds against the converged reference; render time "
        f"the median of those {repeats} renders: the compiled engine's render of a scene"
        f" prepared before"
        f" (raykit.engine.compiled.prepare: arrays, BVH, camera), its time that of the seed's"
        f" sampling and the render, the image's assembly included; raykit's numpy engine's whole"
        f" render\n"
    )
    print("| renderer | sampler | " + " | ".join(f"{n} spp" for n in curves[0].spp) + " |")
    print("|---|---|" + "---|" * len(curves[0].spp))
    for curve in curves:
        cells = [
            f"{e:.5f}, {seconds(t, 1)}" for e, t in zip(curve.rmse(), curve.times(), strict=True)
        ]
        print(f"| {curve.renderer} | {curve.sampler} | " + " | ".join(cells) + " |")
    print()


def print_slopes(slopes: list[tuple[str, Curve]]) -> None:
    print(
        f"## Slopes\n\nThe slope of log RMS error against log samples per pixel, a least-squares"
        f" line through the counts from {FIT_FROM} up, beside the theory's for a pixel's 2D"
        " integral (independent samples -1/2; a stratified set -3/4 where the integrand has an"
        " edge, -1 where it is smooth, Mitchell 1996; a scrambled Sobol' net -3/4 at edges,"
        " Pilleboue et al. 2015, up to about -3/2 where smooth, Owen 1997). Soft shadows and"
        " depth of field integrate over four dimensions, the pixel and the light or the lens:"
        " raykit's jittered sampler stratifies each pair on its own, its cells shuffled against"
        " the pixel's, and its Sobol' sampler scrambles a net of each pair for each pixel, its"
        " points shuffled in the same way (raykit.engine.noise).\n"
    )
    print("| effect | sampler | measured slope | theory |")
    print("|---|---|---|---|")
    for name, curve in slopes:
        print(f"| {name} | {curve.sampler} | {slope(curve):.2f} | {THEORY[curve.sampler]} |")
    print()


def _time_ticks(low: float, high: float) -> list[float]:
    """Ticks of a log time axis from ``low`` to ``high``: 1 and 3 per decade, 1 where that
    crowds them, and the two ends (two digits) where no such tick falls in between."""
    subs = (1, 3) if high < 60 * low else (1,)
    decades = range(math.floor(math.log10(low)), math.ceil(math.log10(high)) + 1)
    ticks = [sub * 10.0**k for k in decades for sub in subs if low <= sub * 10.0**k <= high]
    return ticks if len(ticks) >= 2 else [float(f"{low:.2g}"), float(f"{high:.2g}")]


def plot(path: Path, panels: list[tuple[str, list[Curve]]]) -> None:
    """Per effect, a column of two log-log panels: RMS error against samples per pixel (with a
    line of slope -1/2 through random's first point) above RMS error against render time; one
    legend. Effects side by side, not stacked: a wide figure keeps its text legible on a
    projector (:func:`raykit.io.images.figure_png`) where five rows of panels shrank it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FormatStrFormatter, LogLocator, NullFormatter

    from raykit.io.images import save_figure

    figure, axes = plt.subplots(
        2, len(panels), figsize=(3.4 * len(panels), 6.6), layout="constrained", squeeze=False
    )
    styles = {"random": "o-", "jittered": "s-", "sobol": "^-",
              "independent": "o--", "stratified": "s--"}  # fmt: skip
    legend = {}
    for (name, curves), by_spp, by_time in zip(panels, axes[0], axes[1], strict=True):
        for curve in curves:
            style = styles[curve.sampler]
            (line,) = by_spp.loglog(curve.spp, curve.rmse(), style, label=curve.label)
            by_time.loglog(curve.times(), curve.rmse(), style, color=line.get_color())
            legend.setdefault(curve.label, line)
        first = curves[0]
        spp = np.asarray(first.spp, float)
        (line,) = by_spp.loglog(spp, first.rmse()[0] * (spp / spp[0]) ** -0.5, ":", color="grey")
        legend.setdefault("slope -1/2", line)
        by_spp.set_title(name, fontsize=11)
        by_spp.set_xlabel("samples per pixel")
        by_time.set_xlabel("render time (s)")
        by_spp.set_xticks(first.spp)
        by_time.set_xticks(_time_ticks(*by_time.get_xlim()))
        for ax in (by_spp, by_time):
            ax.yaxis.set_major_locator(LogLocator(subs=(1, 2, 5)))
            for axis in (ax.xaxis, ax.yaxis):
                axis.set_major_formatter(FormatStrFormatter("%g"))
                axis.set_minor_formatter(NullFormatter())
    axes[0][0].set_ylabel("RMS error")
    axes[1][0].set_ylabel("RMS error")
    figure.legend(legend.values(), legend.keys(), loc="outside lower center", ncol=4)
    save_figure(figure, path)
    plt.close(figure)
    print(f"\nwrote {path}")


def machine_line() -> str:
    model, widest = processor()
    return (
        f"Machine: {model or 'an unnamed processor'}, {os.cpu_count()} cores"
        f"{', ' + widest if widest else ''}. raykit's numpy engine renders in one thread (numpy's"
        " own), its compiled engine in as many as there are cores."
    )


def main() -> None:
    parser = arguments(__doc__, "32x24 pictures, 1 to 16 samples per pixel", repeats=4)
    parser.add_argument("--plot", type=Path, help="write the error curves here (PNG)")
    parser.add_argument(
        "--engine", choices=ENGINES, default="auto", help="raykit's engine (default auto)"
    )
    parser.add_argument(
        "--cache",
        type=Path,
        default=Path.home() / ".cache" / "raykit" / "sampling_error",
        help="where the converged references are kept",
    )
    parser.add_argument("--page", type=Path, help=f"default (not with --quick): {PAGE}")
    args = parse(parser)
    with page_of_output(args.page or (None if args.quick else PAGE)):
        run(args)


def run(args: argparse.Namespace) -> None:
    """Measure every effect, print the tables and draw the plot (see the module page)."""
    width, height = (32, 24) if args.quick else (80, 60)
    counts = [1, 4, 16] if args.quick else [1, 4, 16, 64, 256]
    args.reference = 256 if args.quick else 4096
    print(machine_line() + "\n")
    made, missing = effects(width, height)
    for line in missing:
        print(line)
    print()
    panels, slopes = [], []
    for effect in made:
        refused = args.engine == "compiled" and compiled_refuses(effect.scene)
        if refused:  # measured all the same, by the engine that renders it
            print(f"{effect.name}: the compiled engine does not render {refused}: numpy does\n")
        effect_args = argparse.Namespace(**{**vars(args), "engine": "numpy"}) if refused else args
        # the engine of the renders with many samples (a distributed scene)
        many = sampled(effect, counts[-1], "jittered", 1)
        engine = choose(effect_args.engine, replace(effect.scene, sampling=many))
        curves = measure(effect, effect_args, counts)
        print_curves(effect, curves, engine, args.repeats)
        panels.append((effect.name, curves))
        slopes += [(effect.name, c) for c in curves]
    print_slopes(slopes)
    if args.plot:
        plot(args.plot, panels)


if __name__ == "__main__":
    main()

"""The two engines on random scenes of every kind the scene format allows: the same bits?

    python benchmarks/engine_agreement.py [--quick] [--scenes N] [--seed S] [--out DIR]

Makes ``--scenes`` random scene files (default SCENES, 2000; --quick: QUICK_SCENES, 200) from a
numpy Generator seeded with ``--seed``, each as a scene file's contents read by the loader
(``scene_from_dict``), its textures written as PNG files, and renders each with
``engine="numpy"`` (the reference) and ``engine="compiled"``. The scenes span: 0 to 1,500
objects (so that the compiled engine's packets and its one ray at a time, its tile lists, its
tree and its few-object path all run), sphere radii from 1e-4 to 1e3 times the scene's size,
scenes near the origin and 1e5 to 1e6 away, sizes from 1e-3 to 1e3, the camera inside a sphere,
objects behind the camera, billboards tilted, edge-on and behind, textures with holes (alpha
127 and 128 among them), repeated spheres and billboards (exact ties), point lights inside
objects, on their surfaces and at the eye, directional lights along an axis, shadows on and
off, mirrors with max_depth 0 to 4, both projections, fov_angle from 1 to 179 degrees, odd
image sizes (1x1, 1x37, 97x3, primes up to 293), and 1 to 8 x 8 samples per pixel, adaptive or
not.

Each render's ``object_index`` and ``t`` must be the reference's bit for bit (NaN where NaN),
and its ``rgb`` too. One operation is known to differ (raykit.engine.compiled's docstring):
the highlight's power, the C library's pow in the compiled engine and numpy's vectorised power
in the reference. Where the ``rgb`` differs in a scene with a highlight, the reference renders
again with the C library's pow in :func:`raykit.shading.blinn_phong`; if the two then agree bit
for bit, the scene is counted as "agrees but for pow", with its largest difference in units in
the last place and whether its 8-bit image (the PNG) is the same. Anything else is a mismatch:
its scene file (and textures) is saved into ``--out`` (default ``engine_agreement_mismatches``),
named for the seed, the scene's number and the render's samples (``_adaptive``), and the count
of differing pixels and the largest difference are printed.

The page (``docs/benchmarks/engine_agreement.md``) is what this prints on stdout; progress goes
to stderr.
"""

from __future__ import annotations

import json
import platform
import shutil
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests" / "support"))

from common import arguments, parse, processor  # noqa: E402
from libm_power import libm_power  # noqa: E402
from random_scenes import make_textures, random_scene  # noqa: E402

from raykit.io.images import quantize  # noqa: E402
from raykit.io.scene_json import scene_from_dict  # noqa: E402
from raykit.render import render  # noqa: E402

SCENES, QUICK_SCENES = 2000, 200


# -- comparing --------------------------------------------------------------------------------


def same_bits(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Where ``a`` and ``b`` are the same float, NaN where NaN, zeros of the same sign."""
    return ((a == b) & (np.signbit(a) == np.signbit(b))) | (np.isnan(a) & np.isnan(b))


def ulps(a: np.ndarray, b: np.ndarray) -> int:
    """The largest distance between ``a`` and ``b`` in units in the last place (finite
    values of one sign; others count as 2**62)."""
    ia, ib = (np.asarray(x, np.float64).view(np.int64) for x in (a, b))
    finite = np.isfinite(a) & np.isfinite(b) & (np.signbit(a) == np.signbit(b))
    gap = np.where(finite, np.abs(ia - ib), 2**62)
    return int(gap.max()) if gap.size else 0


def compare(scene, options: dict) -> dict:
    """Render ``scene`` with both engines: a row of what differs."""
    # the reference takes the highlight's power (blinn_phong) only for a shiny surface a light
    # reaches (raykit.shading.surface_color)
    has_highlight = scene.materials.any_shiny and bool(scene.lights)
    reference = render(scene, engine="numpy", **options)
    fast = render(scene, engine="compiled", **options)
    row = {
        "index": int((reference.object_index != fast.object_index).sum()),
        "t": int((~same_bits(reference.t, fast.t)).sum()),
        "rgb": int((~same_bits(reference.rgb, fast.rgb).all(axis=2)).sum()),
        "nan": bool(np.isnan(reference.rgb).any() or np.isnan(reference.t).any()),
        "pow only": False,
    }
    with np.errstate(invalid="ignore"):  # inf - inf: the background in both
        row["largest"] = max(
            float(np.nanmax(np.abs(reference.rgb - fast.rgb), initial=0.0)),
            float(np.nanmax(np.abs(reference.t - fast.t), initial=0.0)),
        )
    if row["rgb"] and not row["index"] and not row["t"] and has_highlight:
        with libm_power():
            same_pow = render(scene, engine="numpy", **options)
        if same_bits(same_pow.rgb, fast.rgb).all():
            row["pow only"] = True
            row["ulps"] = ulps(reference.rgb, fast.rgb)
            row["png same"] = bool((quantize(reference.rgb) == quantize(fast.rgb)).all())
    return row


def save(data: dict, out: Path, name: str, work: Path) -> Path:
    """The scene file ``out/name.json`` and its textures under ``out/textures``."""
    (out / "textures").mkdir(parents=True, exist_ok=True)
    for board in data.get("billboards", []):
        if "image" in board:
            shutil.copy(work / board["image"], out / board["image"])
    path = out / f"{name}.json"
    path.write_text(json.dumps(data, indent=1) + "\n")
    return path


def machine() -> str:
    import numba

    model, widest = processor()
    return (
        f"{model or platform.processor() or 'an unnamed processor'} ({widest or 'no AVX2'}), "
        f"{numba.get_num_threads()} numba threads; Python {platform.python_version()}, "
        f"numpy {np.__version__}, numba {numba.__version__}"
    )


def main() -> None:
    parser = arguments(__doc__, f"{QUICK_SCENES} scenes, for CI", repeats=None)
    parser.add_argument("--scenes", type=int, help=f"how many scenes (default {SCENES})")
    parser.add_argument("--seed", type=int, default=35, help="the Generator's seed")
    parser.add_argument("--out", type=Path, default=Path("engine_agreement_mismatches"),
                        help="where scenes that disagree are saved")  # fmt: skip
    args = parse(parser)
    from raykit.engine import choice

    if not choice.compiled_available():
        print(f"The compiled engine cannot run here ({choice.compiled_missing()}): no run.")
        return
    count = args.scenes or (QUICK_SCENES if args.quick else SCENES)
    rng = np.random.default_rng(args.seed)
    print(f"Machine: {machine()}.\n")
    print(f"{count} random scenes from numpy's default_rng({args.seed}).\n")
    tried, failed = Counter(), Counter()
    pow_only, png_differs, largest_ulps, nan_scenes, mismatches = 0, 0, 0, 0, []
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        textures = make_textures(rng, work / "textures")
        for k in range(count):
            data, options, tags = random_scene(rng, textures)
            scene = scene_from_dict(json.loads(json.dumps(data)), source=f"scene {k}", folder=work)
            try:
                row = compare(scene, options)
                bad = bool(row["index"] or row["t"] or (row["rgb"] and not row["pow only"]))
            except Exception as exc:  # an engine that fails on a valid scene is a finding too
                row, bad = {"error": f"{type(exc).__name__}: {exc}"}, True
            tried.update(tags)
            nan_scenes += bool(row.get("nan"))
            if row.get("pow only"):
                pow_only += 1
                png_differs += not row["png same"]
                largest_ulps = max(largest_ulps, row["ulps"])
            if bad:
                failed.update(tags)
                name = f"seed{args.seed}_scene{k}_samples{options['samples']}" + (
                    "_adaptive" if options["adaptive"] else ""
                )
                path = save(data, args.out, name, work)
                mismatches.append((k, path, row, options))
                print(f"scene {k}: MISMATCH {row} -> {path}", file=sys.stderr, flush=True)
            elif k % 10 == 0 or k == count - 1:
                print(f"scene {k + 1}/{count}: agree ({time.perf_counter() - started:.0f} s)",
                      file=sys.stderr, flush=True)  # fmt: skip
    print("| kind of scene (a scene has several) | scenes | mismatches |")
    print("|---|---|---|")
    for tag, n in sorted(tried.items()):
        print(f"| {tag} | {n} | {failed[tag]} |")
    agreed = count - len(mismatches)
    print(
        f"\n{agreed} of {count} scenes agree: object_index and t bit for bit, and rgb bit for "
        f"bit, {pow_only} of them only once the reference takes the C library's pow for the "
        f"highlight (rgb within {largest_ulps} units in the last place as the reference "
        f"stands; the 8-bit image different in {png_differs} of them). "
        f"{len(mismatches)} mismatches. Scenes where the reference gave NaN: {nan_scenes}."
    )
    for k, path, row, options in mismatches:
        what = row.get("error") or (
            f"{row['index']} pixels of another object, {row['t']} of another t, "
            f"{row['rgb']} of another colour; largest difference {row['largest']:.3g}"
        )
        print(f"\n* scene {k} ({options}): {what}; saved as {path}")


if __name__ == "__main__":
    main()

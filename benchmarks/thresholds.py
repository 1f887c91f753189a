"""The engines' tuning constants, each timed on either side of the value the code holds.

    python benchmarks/thresholds.py [--quick] [--repeats N] [--only NAME,NAME]
        [--page docs/benchmarks/thresholds.md]

What it prints is its page, docs/benchmarks/thresholds.md (--page; not with --quick).

A threshold in objects (one method in a scene of fewer objects, another from some count on) is
timed with each method forced, the constant set to 0 and to a count larger than any scene's, on
scenes of object counts on either side of it. * marks the method the code's value chooses at
each count, and the crossover, the smallest count timed from which the other method is faster at
that count and at every larger one, is printed beside the code's value. A size (a tile's side, a
batch, a list's length) is timed at each candidate value on the scenes it serves; * marks the
code's value, and the best is the candidate whose times, each divided by its scene's fastest,
have the smallest geometric mean. Where the code's choice takes more than TOLERANCE times the
faster method's time, or the best candidate's, the line says so: the constants are not changed
by this command, and a disagreement on a busy machine is worth a second run before an edit.

Each time is the median of --repeats renders, the variants of a table taken in turns
(common.medians_in_turns), by the CPU time of the process that renders (time.process_time, one
thread: a while in which a neighbour held the core is not counted).

The numpy engine reads its constants as it renders: this process sets each around its renders.
The compiled engine freezes them into its kernels as they compile, so each value is a child
process of its own (:func:`set_constants`): it sets the constant in every raykit module that
holds it before any kernel compiles, into a new empty cache folder (RAYKIT_CACHE_DIR), then
renders the prepared scenes it is asked for, each timed render right after compile_time.UNTIMED
untimed ones (compile_time.timed_render's protocol); the compile is not timed. raykit itself has
no knob for any of them.

Needs numba (`pip install -e ".[fast]"`) for the compiled engine's constants; without it, says
so and times the numpy engine's.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import json
import math
import os
import pickle
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import (  # noqa: E402
    arguments,
    medians_in_turns,
    page_of_output,
    parse,
    seconds,
    sized,
)
from compile_time import UNTIMED, close, timed_render  # noqa: E402

from raykit.engine import choice  # noqa: E402

REPO = HERE.parent
PAGE = REPO / "docs/benchmarks/thresholds.md"
TOLERANCE = 1.05  # the code's choice within this of the fastest agrees: the noise of a busy
# machine's medians is of that order
ALWAYS = 1 << 40  # objects: more than any scene holds
NRT = "_nrt"  # not a module's constant: numba's option in compiling.KERNEL, for every kernel


@dataclass(frozen=True)
class Threshold:
    """A count of objects in a scene from which the engine turns from one method to another."""

    name: str  # the constant, as the code spells it
    module: str  # the module that holds it
    engine: str  # "numpy" or "compiled"
    methods: tuple[str, str]  # below the threshold, from it on
    inclusive: bool  # the first method up to the value (<=), not below it (<)
    counts: tuple[int, ...]  # objects in the scenes timed
    family: str  # their scenes: "mirrors" or "lit" (:func:`scene`)

    @property
    def forced(self) -> tuple[int, int]:
        """The constant's values that force the first method and the second at every count."""
        return ALWAYS, 0

    def turns_at(self, value: int) -> int:
        """The smallest count at which the code's ``value`` chooses the second method."""
        return value + 1 if self.inclusive else value


@dataclass(frozen=True)
class Size:
    """A size (a tile's side, a batch, a list's length) with the candidates to time."""

    name: str
    module: str
    engine: str
    candidates: tuple
    scenes: tuple[str, ...]
    quick_scenes: tuple[str, ...] = field(default=())


CONSTANTS = [
    Threshold("BVH_FROM", "raykit.engine.regions", "numpy", ("every object", "a BVH"),
              False, (6, 12, 18, 24, 32, 48, 96), "mirrors"),
    Size("TILE", "raykit.engine.tiles", "numpy", (64, 96, 128, 192, 256),
         ("classic", "classic_lit", "cutouts", "mirror_balls", "wide_fov", "sphereflake 4",
          "1,000 spheres 1080p"), ("classic",)),
    Size("CROWDED", "raykit.engine.tiles", "numpy", (4, 8, 16, 24, 48),
         ("classic", "wide_fov", "sphereflake 4", "1,000 spheres 1080p"), ("classic",)),
    Size("POINTS_PER_CALL", "raykit.engine.adaptive", "numpy",
         (1 << 12, 1 << 13, 1 << 14, 1 << 15, 1 << 16),
         ("cutouts, 3x3 adaptive", "sphereflake 4, 3x3 adaptive"), ("cutouts, 3x3 adaptive",)),
    Threshold("DIRECT_HITS", "raykit.engine.compiled.bvh", "compiled", ("each object", "the tree"),
              True, (3, 5, 8, 12, 16, 24), "mirrors"),
    Threshold("DIRECT_LISTS", "raykit.engine.compiled.shadows", "compiled",
              ("each object", "the tree"), True, (16, 32, 64, 96, 128, 256), "lit"),
    Size("SHADOW_CANDIDATES", "raykit.engine.compiled.shadows", "compiled", (8, 16, 32),
         ("classic_lit", "lit 32", "lit 64", "lit 256"), ("classic_lit",)),
    Size("HOLDING_CHUNK", "raykit.engine.compiled.tiles", "compiled", (1, 8, 16),
         ("sphereflake 5",), ("sphereflake 4",)),
    Size(NRT, "raykit.engine.compiled.compiling", "compiled", (False, True),
         ("classic", "classic_lit"), ("classic",)),
]  # fmt: skip


def code_value(constant) -> object:
    """The constant's value in the code. The compiled engine's modules import numba: without
    it, their constant is read from the module's source, where each is a plain number."""
    if constant.name == NRT:
        return False  # compiling.KERNEL's; tests/test_benchmarks.py holds the two the same
    if constant.engine == "numpy" or importlib.util.find_spec("numba") is not None:
        return getattr(importlib.import_module(constant.module), constant.name)
    import raykit

    source = Path(raykit.__file__).parent.joinpath(*constant.module.split(".")[1:])
    for statement in ast.parse(source.with_suffix(".py").read_text()).body:
        targets = statement.targets if isinstance(statement, ast.Assign) else []
        if any(isinstance(target, ast.Name) and target.id == constant.name for target in targets):
            return ast.literal_eval(statement.value)
    raise LookupError(f"{constant.name} is not assigned in {constant.module}")


# ---- scenes -----------------------------------------------------------------------------------


def scene(name: str, quick: bool):
    """``(scene, render options)`` for a table's scene name: an example scene's file stem,
    "lit N" or "mirrors N" (:func:`scenes.lit_spheres`), "sphereflake L", "1,000 spheres
    1080p", each with ", 3x3 adaptive" for 3 x 3 adaptive samples; ``quick``: a quarter of
    the width and height."""
    from raykit.io.scene_json import load_scene
    from scenes import lit_spheres, many_spheres, sphereflake

    base, _, options = name.partition(", ")
    kind, _, number = base.rpartition(" ")
    if kind in ("lit", "mirrors"):
        made = lit_spheres(int(number), mirrors=kind == "mirrors")
    elif kind == "sphereflake":
        made = sphereflake(int(number))
    elif base == "1,000 spheres 1080p":
        made = many_spheres(1000)
    else:
        made = load_scene(REPO / "scenes" / f"{base}.json")
    if quick:
        made = sized(made, max(8, made.camera.width // 4), max(6, made.camera.height // 4))
    return made, dict(samples=3, adaptive=True) if options == "3x3 adaptive" else {}


def scene_names(constant) -> list[str]:
    if isinstance(constant, Threshold):
        return [f"{constant.family} {n}" for n in constant.counts]
    return list(constant.scenes)


# ---- setting a constant -----------------------------------------------------------------------


def holders(module: str, name: str) -> list:
    """The raykit modules imported that hold ``module``'s constant ``name`` under that name
    (those that imported it by name hold a copy): ``module`` first."""
    home = importlib.import_module(module)
    value = getattr(home, name)
    others = [
        m
        for key, m in sorted(sys.modules.items())
        if key.startswith("raykit") and m is not home and getattr(m, name, None) == value
    ]
    return [home, *others]


def set_constants(values: dict[str, object]) -> None:
    """Set each constant ``"module.NAME": value`` in every raykit module that holds it, in a
    process whose compiled engine has compiled nothing yet (else SystemExit): its kernels then
    freeze the new values as they compile. ``NRT``: numba's reference counts on in every
    kernel compiled with them off (compiling.KERNEL's ``_nrt``)."""
    from numba.core.dispatcher import Dispatcher

    import raykit.engine.compiled  # noqa: F401  (every kernel module, none compiled)

    kernels = [
        value
        for key, module in sorted(sys.modules.items())
        if key.startswith("raykit.engine.compiled")
        for value in vars(module).values()
        if isinstance(value, Dispatcher)
    ]
    if any(kernel.signatures for kernel in kernels):
        raise SystemExit("set_constants: a kernel was compiled before its constants were set")
    for key, value in values.items():
        if key == NRT:
            for kernel in kernels:
                if kernel.targetoptions.get("_nrt") is False:
                    kernel.targetoptions["_nrt"] = value
            continue
        module, name = key.rsplit(".", 1)
        for holder in holders(module, name):
            setattr(holder, name, value)


# ---- the numpy engine: in this process ---------------------------------------------------------


def numpy_times(constant, values: list, names: list[str], quick: bool, repeats: int) -> dict:
    """``{(value, scene name): median CPU seconds}`` of the numpy engine's renders with
    ``constant`` set to each of ``values``, scene by scene, the values in turns."""
    from raykit.render import render

    modules = holders(constant.module, constant.name)
    code = getattr(modules[0], constant.name)

    def timer(value, made, options):
        def timed() -> float:
            for module in modules:
                setattr(module, constant.name, value)
            try:
                started = time.process_time()
                render(made, engine="numpy", **options)
                return time.process_time() - started
            finally:
                for module in modules:
                    setattr(module, constant.name, code)

        return timed

    took = {}
    for name in names:
        made, options = scene(name, quick)
        timers = {(value, name): timer(value, made, options) for value in values}
        for each in timers.values():
            each()  # warm-up: the first render of a scene builds what a process keeps
        took.update(medians_in_turns(timers, repeats))
    return took


# ---- the compiled engine: a child process per value -------------------------------------------

# a child: the constants set before any kernel compiles, the scenes prepared and rendered once
# (the compile), then a render (UNTIMED untimed ones and a timed one) per line of its standard
# input, compile_time.timed_render's protocol, its seconds on its output
_CHILD = """
import json, pickle, sys, time
sys.path.insert(0, {here!r})
import thresholds
thresholds.set_constants({values!r})
import numba
from raykit.engine import compiled
with open({scenes!r}, "rb") as file:
    scenes = pickle.load(file)
prepared = {{name: compiled.prepare(scenes[name][0]) for name in {names!r}}}
for each in prepared.values():
    compiled.render.render(each)
print(json.dumps({{name: [each.tiles.size, each.tiles.packets]
                  for name, each in prepared.items()}}), flush=True)
for line in sys.stdin:
    name, _, threads, clock = json.loads(line)
    clock = time.process_time if clock == "cpu" else time.perf_counter
    numba.set_num_threads(threads)
    for _ in range({untimed}):
        compiled.render.render(prepared[name])
    started = clock()
    compiled.render.render(prepared[name])
    print(clock() - started, flush=True)
"""


def start_child(values: dict, names: list[str], scenes_file: Path, cache: Path):
    """A child process with ``values`` set (:func:`set_constants`) compiling into the empty
    folder ``cache``, rendering ``names`` from the pickled scenes in ``scenes_file``."""
    code = _CHILD.format(here=str(HERE), values=values, scenes=str(scenes_file), names=names,
                         untimed=UNTIMED)  # fmt: skip
    errors = tempfile.TemporaryFile()  # a file, not a pipe: nobody reads it while it renders
    child = subprocess.Popen(
        [sys.executable, "-c", code],
        cwd=REPO,
        env={**os.environ, "RAYKIT_CACHE_DIR": str(cache)},
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=errors,
        text=True,
    )
    return child, errors


def ready(child, errors, values: dict) -> dict:
    """The child's first line: each scene's tiles (side, packets), once it has compiled."""
    line = child.stdout.readline()
    if not line:
        child.wait()
        errors.seek(0)
        said = errors.read().decode(errors="replace").strip().splitlines()
        raise SystemExit(f"the child with {values} failed: {said[-1] if said else ''}")
    return json.loads(line)


def variants(constant) -> list:
    """The values a constant is timed at: a threshold's two forced ones, a size's candidates."""
    return list(constant.forced) if isinstance(constant, Threshold) else list(constant.candidates)


def key_of(constant, value) -> tuple:
    """A child's settings for ``constant`` at ``value``: () is the code's own."""
    if value == code_value(constant) and not isinstance(constant, Threshold):
        return ()
    name = constant.name if constant.name == NRT else f"{constant.module}.{constant.name}"
    return ((name, value),)


def compiled_times(constants: list, quick: bool, repeats: int) -> tuple[dict, dict]:
    """``{name: {(value, scene): median CPU seconds}}`` for each compiled constant, from one
    child per setting (two compiling at once), and each child's tiles per scene."""
    wanted: dict[tuple, set] = {}  # a child's settings: the scenes it renders
    for constant in constants:
        for value in variants(constant):
            wanted.setdefault(key_of(constant, value), set()).update(scene_names(constant))
    names = sorted(set().union(*wanted.values()))
    took: dict = {c.name: {} for c in constants}
    tiles: dict = {}
    with tempfile.TemporaryDirectory() as folder:
        scenes_file = Path(folder) / "scenes.pickle"
        scenes_file.write_bytes(pickle.dumps({n: scene(n, quick) for n in names}))
        children = {}
        try:
            keys = list(wanted)
            for first in range(0, len(keys), 2):  # two compiles at once: the machine's cores
                started = {}
                for key in keys[first : first + 2]:
                    cache = Path(folder) / f"cache-{len(children)}"
                    started[key] = start_child(dict(key), sorted(wanted[key]), scenes_file, cache)
                    children[key] = (started[key][0],)
                for key, (child, errors) in started.items():
                    tiles[key] = ready(child, errors, dict(key))
            for constant in constants:
                for name in scene_names(constant):  # scene by scene, the values in turns
                    timers = {
                        (value, name): timed_render(
                            children[key_of(constant, value)][0], name, None, 1, "cpu"
                        )
                        for value in variants(constant)
                    }
                    took[constant.name].update(medians_in_turns(timers, repeats))
        finally:
            close(children)
    return took, tiles


# ---- the tables ---------------------------------------------------------------------------------


def crossover(counts: list[int], first: list[float], second: list[float]) -> int | None:
    """The smallest of ``counts`` from which the second method is faster at it and at every
    larger count; None if it is not faster at the largest."""
    found = None
    for count, a, b in reversed(list(zip(counts, first, second, strict=True))):
        if b >= a:
            break
        found = count
    return found


def threshold_table(constant: Threshold, took: dict, code: int) -> tuple[str, str]:
    """Print a threshold's table; returns (measured, verdict) for the summary."""
    low, high = constant.forced
    first, second = constant.methods
    turns = constant.turns_at(code)
    print(f"| objects | {first} | {second} | {second} / {first} |")
    print("|---|---|---|---|")
    slower = []
    for count in constant.counts:
        name = f"{constant.family} {count}"
        a, b = took[low, name], took[high, name]
        chosen = b if count >= turns else a
        cells = [seconds(a, 1) + "*" * (count < turns), seconds(b, 1) + "*" * (count >= turns)]
        print(f"| {count} | {cells[0]} | {cells[1]} | {b / a:.2f} |")
        if chosen > TOLERANCE * min(a, b):
            slower.append(f"{count} ({chosen / min(a, b):.2f}x)")
    times = [[took[v, f"{constant.family} {n}"] for n in constant.counts] for v in (low, high)]
    found = crossover(list(constant.counts), *times)
    counts = list(constant.counts)
    if found is None:
        measured = f"{second} not faster at {counts[-1]} objects"
    elif found == counts[0]:
        measured = f"{second} faster from the fewest timed, {found}, on"
    else:
        before = counts[counts.index(found) - 1]
        measured = f"{second} faster from {found} objects on (not at {before})"
    verdict = (
        "agrees"
        if not slower
        else "disagrees: the code's choice is slower at " + ", ".join(slower) + " objects"
    )
    print(
        f"\nIn the code: {constant.name} = {code}, {second} from {turns} objects on; measured: "
        f"{measured}; {verdict}."
    )
    return measured, verdict


def size_table(constant: Size, took: dict, code, names: list[str]) -> tuple[str, str]:
    """Print a size's table; returns (measured, verdict) for the summary."""
    values = constant.candidates
    print("| scene | " + " | ".join(str(v) for v in values) + " |")
    print("|---|" + "---|" * len(values))
    ratios = {v: [] for v in values}
    for name in names:
        fastest = min(took[v, name] for v in values)
        for v in values:
            ratios[v].append(took[v, name] / fastest)
        cells = [seconds(took[v, name], 1) + "*" * (v == code) for v in values]
        print(f"| {name} | " + " | ".join(cells) + " |")
    mean = {v: math.exp(statistics.fmean(math.log(r) for r in ratios[v])) for v in values}
    print(
        "| time / the scene's fastest, geometric mean | "
        + " | ".join(f"{mean[v]:.2f}" + "*" * (v == code) for v in values)
        + " |"
    )
    best = min(values, key=lambda v: mean[v])
    verdict = (
        "agrees"
        if mean[code] <= TOLERANCE * mean[best]
        else f"disagrees: the code's value takes {mean[code] / mean[best]:.2f}x the best's time"
    )
    print(f"\nIn the code: {constant.name} = {code}; measured best: {best}; {verdict}.")
    return str(best), verdict


def describe(constant) -> str:
    if constant.name == NRT:
        return (
            "numba's reference counts (_nrt) in every kernel but those that make arrays: off in "
            "the code (compiling.KERNEL), on to compare"
        )
    if isinstance(constant, Threshold):
        first, second = constant.methods
        up_to = "up to" if constant.inclusive else "below"
        return (
            f"{constant.engine} engine: {first} {up_to} {constant.name} objects, {second} "
            f"beyond, each forced; {constant.family} N: N - 1 lit spheres"
            f"{' (every other a mirror)' * (constant.family == 'mirrors')} over a ground "
            "billboard (scenes.lit_spheres)"
        )
    return f"{constant.engine} engine: each candidate value"


def main() -> None:
    parser = arguments(__doc__, "quarter-size scenes, fewer of them", repeats=5)
    parser.add_argument("--only", help="these constants only, by name, commas between")
    parser.add_argument("--page", type=Path, help="write what it prints here (not with --quick)")
    args = parse(parser)
    chosen = CONSTANTS
    if args.only:
        asked = args.only.split(",")
        unknown = [n for n in asked if n not in [c.name for c in CONSTANTS]]
        if unknown:
            raise SystemExit(f"--only: no constant {unknown[0]!r}")
        chosen = [c for c in CONSTANTS if c.name in asked]
    if args.quick:
        chosen = [
            c if isinstance(c, Threshold) else Size(**{**vars(c), "scenes": c.quick_scenes})
            for c in chosen
        ]
        chosen = [
            Threshold(**{**vars(c), "counts": c.counts[:: len(c.counts) - 1]})
            if isinstance(c, Threshold)
            else c
            for c in chosen
        ]
    fast = choice.compiled_available()
    with page_of_output(None if args.quick else args.page):
        began = time.perf_counter()
        print(
            f"Medians of {args.repeats} renders in turns, CPU time, 1 thread; load average at "
            f"the start {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores.\n"
        )
        if not fast:
            print('numba is not installed (pip install -e ".[fast]"): the numpy engine alone.\n')
        took: dict = {}
        for constant in chosen:
            if constant.engine == "numpy":
                took[constant.name] = numpy_times(
                    constant, variants(constant), scene_names(constant), args.quick, args.repeats
                )
        compiled = [c for c in chosen if c.engine == "compiled" and fast]
        tiles: dict = {}
        if compiled:
            times, tiles = compiled_times(compiled, args.quick, args.repeats)
            took |= times
        summary = []
        for constant in CONSTANTS:
            code = code_value(constant)
            run = next((c for c in chosen if c.name == constant.name), None)
            if run is None or run.name not in took:
                summary.append((constant, code, "not run", ""))
                continue
            print(f"## {constant.name} ({constant.module})\n")
            print(describe(constant) + "\n")
            if isinstance(run, Threshold):
                measured, verdict = threshold_table(run, took[run.name], code)
            else:
                measured, verdict = size_table(run, took[run.name], code, scene_names(run))
            print()
            summary.append((constant, code, measured, verdict))
        print("## Summary\n")
        print("| constant | module | in the code | measured | |")
        print("|---|---|---|---|---|")
        for constant, code, measured, verdict in summary:
            print(f"| {constant.name} | {constant.module} | {code} | {measured} | {verdict} |")
        if tiles:
            packets = sorted({n for each in tiles.values() for n, (_, p) in each.items() if not p})
            print(
                "\nThe compiled engine's viewing rays go one at a time (where HOLDING_CHUNK "
                f"serves) in: {', '.join(packets) or 'none of the scenes'}; in packets elsewhere."
            )
        print(
            f"\nLoad average at the end {os.getloadavg()[0]:.1f}; the run took "
            f"{(time.perf_counter() - began) / 60:.0f} min."
        )


if __name__ == "__main__":
    main()

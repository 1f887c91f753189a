"""What the compiled engine's first use costs, and its renders against the engine it replaced.

    python benchmarks/compile_time.py [--quick] [--compiles N] [--repeats N] [--before REV]
        [--before-compile] [--cpus NAME,NAME] [--page docs/benchmarks/compile_time.md]

What it prints is its page, docs/benchmarks/compile_time.md (--page; not with --quick or
--cpus-only).

1. The first use from an empty cache: whole processes of `raykit render SCENE -o OUT.png
   --engine compiled` on scenes/classic.json (flat), scenes/classic_lit.json (lit),
   scenes/mirror_balls.json (lit, with mirrors), and stage 5's distributed entry points:
   scenes/soft_shadows.json (still), scenes/glossy.json (still, with mirrors) and
   scenes/motion_blur.json (moving), each with a new empty cache folder
   (RAYKIT_CACHE_DIR), taken in turns: wall time, CPU time (the
   process's user + system seconds: what the compile costs where no neighbour takes a core)
   and peak memory (its largest resident set, from os.wait4). Then the same render again from
   the cache it left; --compiles rounds of each (median). Each entry point's kernels, each
   with its own compile seconds in those runs (its callees' not counted; numba's compile
   events), are listed, and go to
   raykit/engine/compiled/compile_seconds.json, which the progress line reads while it
   compiles (not with --quick).
2. With --before REV: the compiled engine as it was at git revision REV, whatever its layout:
   REV's whole tree (git archive) unpacked under ~/.cache/raykit and put first on the child's
   sys.path, so that raykit, the engine and the reference it repeats all come from REV, with
   its own cache folder beside it (the first run compiles it), and this one, each in a child
   process of its own, rendering every example scene REV reads and the benchmark scenes
   prepared: medians of --repeats renders and their ratio, on every core, then on one (which a
   neighbour's work on the other core slows less), then on one timed by the CPU time the child
   process took (time.process_time: a while in which a neighbour held the core is not
   counted, so on a busy machine these ratios hold best; on every core they would count the
   threads' waits).
   Not in one process: both engines pass NamedTuples of the same
   names and fields (Arrays, Tiles, Tree) to their kernels, and numba's dispatcher, which finds
   the compiled code for a call's arguments by a fingerprint of their types, gives two such
   classes one fingerprint, so the engine that rendered second in the process took numba's slow
   path on every call (its arguments typed in Python), whichever it was. Scene by scene, the
   two engines' renders in turns, each timed render right after UNTIMED untimed ones: the next
   few renders after one of a large image (1,000 spheres at 1080p) take longer, whichever
   engine made either, so in rounds of every scene an engine whose small scene came right after
   the other engine's large one lost, by the order alone. With --before-compile, part 1 times
   REV's first uses too, in turns with this tree's, each from a new empty cache folder of its
   own (of the scenes REV reads: its own tree has them, of the same scene format version).
3. With --cpus NAME,NAME (e.g. native,haswell): the compiled engine's prepared renders of the
   benchmark scenes (CPU_SCENES) compiled for each CPU, in one child process per CPU
   (NUMBA_CPU_NAME=NAME and NUMBA_CPU_FEATURES empty, so that the features are NAME's own and
   not this machine's: haswell is AVX2 without AVX-512; native is this machine), each
   compiling into a new cache folder of its own (numba shows the code only of what it
   compiled), with the tiles raykit.engine.compiled.tile_side chooses and with each layout of
   CPU_LAYOUTS, all taken in turns (each child times its own renders, each timed render right
   after UNTIMED untimed ones): medians of --repeats renders on one core (on both, the two
   children's thread pools stood in each other's way); and which instructions the packet loop
   compiles to (the vector registers primary_rays' code names: ymm holds 4 float64, zmm 8).

Needs numba (`pip install -e ".[fast]"`).
"""

from __future__ import annotations

import importlib
import io
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from common import (  # noqa: E402
    arguments,
    medians_in_turns,
    numba_cpu,
    page_of_output,
    parse,
    seconds,
)

from raykit.engine import choice  # noqa: E402

REPO = HERE.parent
SCENES = REPO / "scenes"
# part 1's scenes, one per entry point: flat, lit, lit with mirrors, and stage 5's distributed
# ones: still, still with mirrors, moving
FIRST_USE = ["classic", "classic_lit", "mirror_balls", "soft_shadows", "glossy", "motion_blur"]
PAGE = REPO / "docs/benchmarks/compile_time.md"

# a child's render, with each kernel's own compile seconds and (if LOOK_FOR_CALLS: only from
# an empty cache, since a kernel loaded from the cache shows no code) the calls of per-ray
# kernels left in the code it compiled (calls_left) written to the file given
_FIRST_USE_CHILD = """
{imports}
import json
from raykit.cli import main
from raykit.engine.compiled.compiling import compile_clock
with compile_clock({entry!r}, show=False) as clock:
    status = main(["render", {scene!r}, "-o", {out!r}, "--engine", "compiled"])
if {look_for_calls!r}:
    from compile_time import calls_left
    calls = calls_left()
else:
    calls = []
open({seconds!r}, "w").write(json.dumps([clock.own, calls]))
sys.exit(status)
"""


def calls_left() -> list[str]:
    """The calls of per-ray kernels (``@njit(**ONE_RAY)``, which LLVM inlines where its rule
    finds that it pays, and ``@njit(**INLINED)``, which it always inlines) left in the machine
    code of the kernels this process compiled, as ``caller -> kernel``: none if LLVM inlined
    every one (a kernel loaded from the cache shows no code)."""
    import inspect
    import pkgutil

    from numba.core.registry import CPUDispatcher

    import raykit.engine.compiled as package

    kernels = {}
    for module in pkgutil.iter_modules(package.__path__):
        for name, value in vars(
            importlib.import_module(f"{package.__name__}.{module.name}")
        ).items():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__.startswith(
                package.__name__
            ):
                kernels[name] = value
    per_ray = ("@njit(**ONE_RAY)", "@njit(**INLINED)")
    one_ray = {name for name, kernel in kernels.items()
               if inspect.getsource(kernel.py_func).startswith(per_ray)}  # fmt: skip
    # each compiled version's symbol, as the machine code of a call of it names it
    symbols = {
        result.fndesc.mangled_name: name
        for name in one_ray
        for result in kernels[name].overloads.values()
    }
    left = set()
    for caller, kernel in kernels.items():
        for signature in kernel.signatures:
            try:
                code = kernel.inspect_llvm(signature)
            except Exception:  # loaded from the cache: no code to read
                continue
            for symbol in re.findall(r'call [^@\n]*@"?(_ZN[^"(\s]+)', code):
                callee = symbols.get(symbol)
                if callee is not None and callee != caller:
                    left.add(f"{caller} -> {callee}")
    return sorted(left)


def run_child(code: str, **env) -> dict:
    """Run ``python -c code`` and wait for it: its wall seconds, CPU seconds (user + system)
    and peak resident memory in MB, from the kernel's account of that one process."""
    started = time.perf_counter()
    child = subprocess.Popen(
        [sys.executable, "-c", code],
        cwd=REPO,
        env={**os.environ, **env},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    stderr = child.stderr.read()
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - started
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        raise SystemExit(f"a child failed:\n{stderr.decode()[-2000:]}")
    return {
        "wall": wall,
        "cpu": usage.ru_utime + usage.ru_stime,
        "peak_mb": usage.ru_maxrss / 1024,  # Linux gives kilobytes
    }


def first_use(repeats: int, folder: Path, revision: str | None = None) -> tuple[dict, dict, list]:
    """Part 1: per scene, the medians of its first use and of a run from the cache it left
    (with ``revision``, also that revision's, :func:`revision_tree`, in turns with this tree's,
    each with its own new cache folder); each entry point's kernels' own compile seconds
    (median per kernel, this tree's); and the calls of per-ray kernels left in the code
    compiled (:func:`calls_left`)."""
    from raykit.io.scene_json import load_scene

    entries = {name: choice.entry_point(load_scene(SCENES / f"{name}.json")) for name in FIRST_USE}
    label = {"now": "", revision: f", at {revision}"}
    turns = [
        (name, engine)
        for name in FIRST_USE
        for engine in ["now"] + ([revision] if revision and revision_reads(name, revision) else [])
    ]  # fmt: skip
    runs: dict = {(name, when + label[engine]): [] for name, engine in turns
                  for when in ("empty", "cached")}  # fmt: skip
    left: set = set()
    own: dict = {entry: {} for entry in entries.values()}
    for round_ in range(repeats):
        for name, engine in turns if round_ % 2 == 0 else turns[::-1]:
            cache = folder / f"cache-{name}-{engine}-{round_}"
            spent = folder / f"seconds-{name}-{engine}-{round_}.json"
            imports, environment = engine_environment(engine, str(cache))
            code = {
                when: _FIRST_USE_CHILD.format(
                    imports=imports,
                    entry=entries[name],
                    scene=str(SCENES / f"{name}.json"),
                    out=str(folder / f"{name}.png"),
                    seconds=str(spent),
                    # its work is timed too; this tree's kernels only
                    look_for_calls=round_ == 0 and when == "empty" and engine == "now",
                )
                for when in ("empty", "cached")
            }
            for when in ("empty", "cached"):
                runs[(name, when + label[engine])].append(run_child(code[when], **environment))
                if when == "empty" and engine == "now":
                    seconds_of, calls = json.loads(spent.read_text())
                    for kernel, took in seconds_of.items():
                        own[entries[name]].setdefault(kernel, []).append(took)
                    left.update(calls)
    medians = {
        key: {figure: statistics.median(run[figure] for run in values) for figure in values[0]}
        for key, values in runs.items()
    }
    table = {
        entry: {kernel: round(statistics.median(spent), 2) for kernel, spent in kernels.items()}
        for entry, kernels in own.items()
    }
    return medians, table, sorted(left)


def revision_reads(name: str, revision: str) -> bool:
    """Whether git ``revision`` of raykit reads scene ``name`` as this tree has it: its own tree
    (:func:`revision_tree`) has the scene, of the same scene format version (an older revision
    refuses a later version's file)."""

    def version(path: Path) -> int | None:
        return json.loads(path.read_text()).get("version", 1) if path.exists() else None

    ours = version(SCENES / f"{name}.json")
    return ours == version(revision_tree(revision) / "scenes" / f"{name}.json")


def revision_tree(revision: str) -> Path:
    """The whole source tree of git ``revision`` (``git archive``), unpacked once under
    ~/.cache/raykit/before-SHA/tree, whatever its engine's layout: a child process that puts it
    first on sys.path imports raykit, and so its engine and the reference it repeats, from
    there. git archive gives every file the commit's time, so numba's cache of it stays valid
    from one run to the next."""
    sha = subprocess.run(
        ["git", "rev-parse", "--verify", f"{revision}^{{commit}}"],
        cwd=REPO,
        check=True,
        capture_output=True,
        text=True,
    ).stdout.strip()
    tree = Path(os.path.expanduser("~/.cache")) / "raykit" / f"before-{sha[:12]}" / "tree"
    if not (tree / "raykit" / "__init__.py").exists():
        unpacking = tree.with_name("unpacking")
        shutil.rmtree(unpacking, ignore_errors=True)
        unpacking.mkdir(parents=True)
        archive = subprocess.run(
            ["git", "archive", "--format=tar", sha], cwd=REPO, check=True, capture_output=True
        ).stdout
        with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
            tar.extractall(unpacking, filter="tar")
        unpacking.rename(tree)
    return tree


def engine_environment(engine: str, cache: str | None = None) -> tuple[str, dict]:
    """The lines a child process starts with to import raykit from ``engine`` ("now": this
    tree; else a git revision, :func:`revision_tree`), and the environment it runs in: its
    cache folder ``cache`` (None: this tree's default; a revision's own beside its tree)."""
    lines = [f"import sys; sys.path.insert(0, {str(HERE)!r})"]
    if engine != "now":
        tree = revision_tree(engine)
        lines.append(f"sys.path.insert(0, {str(tree)!r})")
        cache = cache or str(tree.with_name("cache"))
    return "\n".join(lines) + "\n", {"RAYKIT_CACHE_DIR": cache} if cache else {}


def before_and_after(revision: str, repeats: int, quick: bool) -> None:
    """Part 2: prepared renders, this engine and ``revision``'s, each in a child process of its
    own, in turns (see the module's docstring for why not in one process)."""
    import numba
    from engines import benchmark_scenes

    names = [  # what both revisions read: the generated scenes, and the example scenes REV has
        name
        for name in benchmark_scenes(quick)
        if not (SCENES / f"{name}.json").exists() or revision_reads(name, revision)
    ]
    children = {
        engine: render_child(engine, names, [None], None, quick) for engine in (revision, "now")
    }
    took = {}
    # (threads, clock): on every core and on one, by the wall clock; and on one by the CPU
    # time the render took, which leaves out the whiles a neighbour held the core
    timings = [(n, "wall") for n in sorted({numba.config.NUMBA_NUM_THREADS, 1}, reverse=True)]
    timings.append((1, "cpu"))
    try:
        for timing in timings:  # one thread: a busy
            for name in names:  # neighbour on one core holds up no render of it; scene by scene
                took.update(
                    medians_in_turns(
                        {
                            (engine, name, timing): timed_render(child, name, None, *timing)
                            for engine, (child, _, _) in children.items()
                        },
                        repeats,
                    )
                )
    finally:
        close(children)
    print(
        f"\n2. prepared renders, median of {repeats} in turns, each engine in a process of its "
        "own; the last three columns time each render by the CPU time its process took (time."
        "process_time), not the wall clock\n"
    )
    print(
        "| scene | "
        + " | ".join(
            f"at {revision}, {n} thread(s){', CPU time' * (clock == 'cpu')} | now | now / "
            f"{revision}"
            for n, clock in timings
        )
        + " |"
    )
    print("|---|" + "---|---|---|" * len(timings))
    for name in names:
        cells = []
        for timing in timings:
            old, new = took[(revision, name, timing)], took[("now", name, timing)]
            cells += [seconds(old, 1), seconds(new, 1), f"{new / old:.2f}"]
        print(f"| {name} | " + " | ".join(cells) + " |")


CPU_SCENES = ["classic", "classic_lit", "sphereflake 4", "1,000 spheres 1080p"]
CPU_LAYOUTS = [(4, False), (8, True), (16, True)]  # (tile side, packets) besides the choice
# untimed renders before each timed one in parts 2 and 3: after the other child's renders, a
# child's next two or three took longer (one untimed was not enough)
UNTIMED = 3

# a child of parts 2 and 3: one engine (its IMPORTS, engine_environment: this tree's or a git
# revision's), the scenes prepared with each layout (None: the
# engine's own choice), then a render (UNTIMED untimed ones and a timed one) per line of its
# standard input, its seconds on its output
_RENDER_CHILD = """
{imports}
import json, re, time
import numba
from engines import benchmark_scenes
from raykit.engine import compiled as engine
# the render function: engine.render.render since the renderer's loop is a module of that
# stem; a revision before it bound the function itself on the package
render = getattr(engine.render, "render", engine.render)
scenes = benchmark_scenes({quick!r}, format_v1_only=True)
if set({names!r}) - set(scenes):  # example scenes of a later format, which this revision reads
    from raykit.io.scene_json import load_scene
    scenes.update({{name: load_scene({scenes_folder!r} + "/" + name + ".json")
                   for name in set({names!r}) - set(scenes)}})
prepared = {{}}
for name in {names!r}:
    base = engine.prepare(scenes[name])
    for layout in {layouts!r}:
        tiles = base.tiles if layout is None else engine.screen_tiles(
            scenes[name], base.arrays, *layout)
        prepared[name, layout] = base._replace(tiles=tiles)
        render(prepared[name, layout])
registers = {{}}
for asm in engine.primary_rays.inspect_asm().values():
    for kind in ("xmm", "ymm", "zmm"):
        registers[kind] = registers.get(kind, 0) + len(re.findall(kind, asm))
chosen = {{name: [each.tiles.size, each.tiles.packets]
          for (name, layout), each in prepared.items() if layout is None}}
print(json.dumps([registers, chosen]), flush=True)
for line in sys.stdin:
    name, layout, threads, clock = json.loads(line)
    clock = time.process_time if clock == "cpu" else time.perf_counter
    numba.set_num_threads(threads)
    each = prepared[name, None if layout is None else tuple(layout)]
    for _ in range({untimed}):
        render(each)
    started = clock()
    render(each)
    print(clock() - started, flush=True)
"""


def render_child(engine: str, names: list[str], layouts: list, cache: str | None, quick: bool,
                 **env) -> tuple:  # fmt: skip
    """A child process of ``engine`` ("now" or a git revision) with ``names``' scenes prepared
    in ``layouts``, ready (kernels loaded or compiled; ``cache``: the compiled engine's cache
    folder, None: its default), and what its first line told: the vector registers of its
    packet loop (empty unless compiled in the child) and the tiles chosen."""
    imports, environment = engine_environment(engine, cache)
    code = _RENDER_CHILD.format(imports=imports, quick=quick, names=names, layouts=layouts,
                                untimed=UNTIMED, scenes_folder=str(SCENES))  # fmt: skip
    errors = tempfile.TemporaryFile()  # a file, not a pipe: nobody reads it while it renders
    child = subprocess.Popen(
        [sys.executable, "-c", code],
        cwd=REPO,
        env={**os.environ, **env, **environment},
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=errors,
        text=True,
    )
    line = child.stdout.readline()
    if not line:
        child.wait()
        errors.seek(0)
        said = errors.read().decode(errors="replace").strip().splitlines()
        raise SystemExit(
            f"the child rendering with the engine {engine} failed: {said[-1] if said else ''}"
        )
    return (child, *json.loads(line))


def timed_render(child, scene: str, layout, threads: int, clock: str = "wall"):
    """A timer for :func:`medians_in_turns`: ``child`` renders ``scene`` once and says how long
    it took, by the wall clock or (``clock`` "cpu") by the CPU time its process took."""

    def timed() -> float:
        child.stdin.write(json.dumps([scene, layout, threads, clock]) + "\n")
        child.stdin.flush()
        return float(child.stdout.readline())

    return timed


def close(children: dict) -> None:
    for child, *_ in children.values():
        child.stdin.close()
        child.wait()


def cpu_children(names: list[str], folder: Path) -> dict:
    """Part 3's children (:func:`render_child`), one per CPU name, each compiling into a new
    cache folder of its own (numba shows the code only of what it compiled)."""
    layouts = [None, *CPU_LAYOUTS]
    children = {}
    for name in names:
        cache = str(folder / f"cpu-cache-{name}")
        children[name] = render_child("now", CPU_SCENES, layouts, cache, False, **numba_cpu(name))
    return children


def cpus(names: list[str], repeats: int) -> None:
    """Part 3: the compiled engine's prepared renders, compiled for each CPU of ``names``."""
    layouts = [None, *CPU_LAYOUTS]
    with tempfile.TemporaryDirectory() as folder:
        children = cpu_children(names, Path(folder))
        took = {}
        thread_counts = [1]  # see the docstring
        try:
            for threads in thread_counts:
                for scene in CPU_SCENES:  # scene by scene, as part 2
                    took.update(
                        medians_in_turns(
                            {
                                (cpu, scene, layout, threads): timed_render(
                                    children[cpu][0], scene, layout, threads
                                )
                                for cpu in names
                                for layout in layouts
                            },
                            repeats,
                        )
                    )
        finally:
            close(children)
    print(f"\n3. prepared renders compiled for each CPU, median of {repeats} in turns\n")
    for cpu, (_, registers, _) in children.items():
        listed = ", ".join(f"{count} {kind}" for kind, count in registers.items())
        print(f"- {cpu}: the packet loop (primary_rays) names {listed}")
    first = names[0]
    print(
        "\n| scene | threads | CPU | tile_side's choice | "
        + " | ".join(f"{side} px{', packets' if packets else ''}" for side, packets in CPU_LAYOUTS)
        + f" | choice / {first}'s |"
    )
    print("|---|---|---|---|" + "---|" * len(CPU_LAYOUTS) + "---|")
    for threads in thread_counts:
        for scene in CPU_SCENES:
            for cpu in names:
                side, packets = children[cpu][2][scene]
                choice_ = f"{side} px{', packets' if packets else ''}: "
                cells = [choice_ + seconds(took[(cpu, scene, None, threads)], 1)]
                cells += [seconds(took[(cpu, scene, layout, threads)], 1) for layout in CPU_LAYOUTS]
                ratio = took[(cpu, scene, None, threads)] / took[(first, scene, None, threads)]
                print(f"| {scene} | {threads} | {cpu} | " + " | ".join(cells) + f" | {ratio:.2f} |")


def main() -> None:
    parser = arguments(__doc__, "one round of first uses, the example scenes only", repeats=9)
    parser.add_argument("--compiles", type=int, default=3, help="first uses per scene (median)")
    parser.add_argument("--before", metavar="REV", help="time REV's compiled engine besides")
    parser.add_argument(
        "--before-compile", action="store_true", help="and REV's first uses (minutes)"
    )
    parser.add_argument(
        "--cpus", metavar="NAME,NAME", help="time renders compiled for these CPUs (3.)"
    )
    parser.add_argument("--cpus-only", action="store_true", help="only part 3")
    parser.add_argument(
        "--page", type=Path, help=f"default (not with --quick or --cpus-only): {PAGE}"
    )
    args = parse(parser)
    if not choice.compiled_available():
        print('numba is not installed (pip install -e ".[fast]"): nothing to time.')
        return
    if args.cpus_only and args.cpus:
        with page_of_output(args.page):
            print(f"on {os.cpu_count()} cores\n")
            cpus(args.cpus.split(","), args.repeats)
        return
    with page_of_output(args.page or (None if args.quick else PAGE)):
        print(f"on {os.cpu_count()} cores\n")
        all_parts(args)


def all_parts(args) -> None:
    """Part 1, then 2 and 3 as ``args`` ask."""
    from raykit.io.scene_json import load_scene

    with tempfile.TemporaryDirectory() as folder:
        rounds = 1 if args.quick else args.compiles
        revision = args.before if args.before_compile else None
        medians, table, left = first_use(rounds, Path(folder), revision)
    print(f"1. raykit render SCENE --engine compiled, whole processes, median of {rounds}\n")
    print("| scene | entry point | cache | wall time | CPU time | peak memory |")
    print("|---|---|---|---|---|---|")
    for (name, when), figures in medians.items():
        entry = choice.entry_point(load_scene(SCENES / f"{name}.json"))
        print(
            f"| {name} | {entry} | {when} | {figures['wall']:.1f} s | {figures['cpu']:.1f} s "
            f"| {figures['peak_mb']:.0f} MB |"
        )
    if revision:
        ratios = []
        for name in (name for name in FIRST_USE if revision_reads(name, revision)):
            now, then = medians[(name, "empty")], medians[(name, f"empty, at {revision}")]
            ratios.append(
                f"{name} {now['wall'] / then['wall']:.2f} (CPU time {now['cpu'] / then['cpu']:.2f})"
            )
        print(f"\nFirst use from an empty cache, now / at {revision}: {', '.join(ratios)}.")
    print(
        "\nWhat each entry point compiles from an empty cache: its kernels, each with its own"
        " compile seconds (median), slowest first."
    )
    for entry, kernels in table.items():
        every = sorted(kernels.items(), key=lambda item: -item[1])
        listed = ", ".join(f"{kernel} {took:.1f} s" for kernel, took in every)
        print(f"\n{entry}: {len(kernels)} kernels, {sum(kernels.values()):.1f} s: {listed}.")
    print(
        "\nCalls of per-ray kernels left in the code compiled (ONE_RAY, which LLVM inlines where "
        "its rule finds that it pays; INLINED, which it always inlines, should be none of them): "
        + (", ".join(left) if left else "none")
        + "."
    )
    if not args.quick:
        from raykit.engine.compiled.compiling import SECONDS_TABLE

        SECONDS_TABLE.write_text(json.dumps(table, indent=1) + "\n")
        print(f"\nwrote {SECONDS_TABLE.relative_to(REPO)}")
    if args.before:
        before_and_after(args.before, args.repeats, args.quick)
    if args.cpus:
        cpus(args.cpus.split(","), args.repeats)


if __name__ == "__main__":
    main()

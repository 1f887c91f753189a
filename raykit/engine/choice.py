"""Which engine renders: the numpy one, or the compiled one (:mod:`raykit.engine.compiled`).

``engine="numpy"`` is the lecture's loop over numpy arrays (:func:`raykit.render.render`), and
always there. ``engine="compiled"`` needs numba (``pip install "raykit[fast]"``) and renders the
same bits in machine code. ``engine="auto"`` (the default) takes the compiled engine only when
the whole process is faster with it: numba is installed, the kernels the scene needs are
already compiled and cached (a first compile takes longer than most renders), the render is
float64, and the numpy engine would take longer than loading numba and the kernels costs
(``AUTO_FROM``, measured by ``raykit bench``). So a small render never pays for numba, and
nothing here imports it.

A distributed scene (stage 5) is judged by the same rule, with its own estimate of the numpy
engine's time: its sample rays (width x height x ``render.samples_per_pixel``) at the numpy
engine's time per sample ray of a distributed render (``NUMPY_SECONDS_PER_RAY["distributed"]``,
more than a lit pinhole ray's: each sample draws its uniform numbers, and its batches are a
tile's pixels at one sample), and its own kernels (``trace_sampled``, ``trace_sampled_mirrors``
or ``trace_moving``: :func:`entry_point`) compiled and cached.
Loading those costs a process about what a lit scene's kernels cost, and the compiled engine
saves about the same share of the numpy engine's time (``python benchmarks/engines.py``
prints both), so the one threshold ``AUTO_FROM`` serves.
The compiled engine renders such a scene from the same numbers (:mod:`raykit.engine.noise`),
so the choice never changes a byte, only the time.

A scene whose spheres move (motion blur) is a distributed scene to this rule, estimated at the
same time per sample ray. Both engines then test every object for every ray (no tile, box or
tree bounds a moving sphere), so the numpy engine takes longer per ray than the estimate says
in a scene of many objects, and the compiled engine saves a larger share: the rule errs
towards numpy there, which costs time, never a byte.
"""

from __future__ import annotations

import ast
import functools
import hashlib
import importlib.util
import json
import os
import runpy
import tempfile
from pathlib import Path

import numpy as np

from raykit.scene import Scene
from raykit.shading import needs_shading

ENGINES = ("auto", "numpy", "compiled")
FAST_EXTRA = 'pip install "raykit[fast]"'
STARTER_KIT = (
    "is not in the starter kit (it would give the solutions away): render with your own "
    "functions, --engine numpy (what auto picks here); for a quicker look, make the picture "
    "smaller (the camera's width and height in the scene file)"
)
COMPILED_SOURCE = Path(__file__).with_name("compiled")  # the package of kernels
# The numpy engine's time per ray, flat and shaded, and per sample ray of a distributed render,
# and what loading numba and the cached kernels costs a process: measured by
# benchmarks/engines.py (`raykit bench` prints them again on yours)
NUMPY_SECONDS_PER_RAY = {"flat": 2.0e-7, "lit": 8.0e-7, "distributed": 1.1e-6}
AUTO_FROM = 0.5  # seconds of numpy rendering from which the compiled engine wins, load included


class EngineUnavailable(RuntimeError):
    """The compiled engine was asked for where it cannot run; the message says what to do."""


def compiled_missing() -> str:
    """Why the compiled engine cannot run here, and what to do instead."""
    if not COMPILED_SOURCE.exists():
        return STARTER_KIT
    return f"needs numba, which is not installed: {FAST_EXTRA}"


def compiled_available() -> bool:
    """Whether the compiled engine can run here: numba is installed (found, not imported) and
    this copy of raykit has the engine (a student's starter kit does not)."""
    return COMPILED_SOURCE.exists() and importlib.util.find_spec("numba") is not None


def twin_table() -> dict:
    """The twin table (:mod:`raykit.engine.compiled.twins`) as its module's globals, read from
    its file: importing it through its package would import numba."""
    return runpy.run_path(str(COMPILED_SOURCE / "twins.py"))


def frozen_modules() -> list[str]:
    """The modules besides the kernels' own whose source the kernels depend on, sorted: those
    whose functions they repeat (:func:`twin_table`), and those whose globals they read
    (:func:`_modules_read`), found in the kernels' source, so that the list cannot drift from
    it. Reading the sources' syntax takes a tenth of a second or more, in every process that
    loads the engine: the list is kept on disk beside the caches, under a hash of every source
    of this copy of raykit, and read from there while none changes."""
    package = COMPILED_SOURCE.parent.parent
    digest = hashlib.sha256(os.path.abspath(package).encode())
    for source in sorted(package.rglob("*.py")):
        digest.update(str(source.relative_to(package)).encode() + b"\0" + source.read_bytes())
    for base in _bases():
        kept = Path(base) / "raykit" / f"frozen-{digest.hexdigest()[:16]}.json"
        try:
            return json.loads(kept.read_text())
        except (OSError, ValueError):
            pass
    found = _frozen_modules()
    for base in _bases():
        kept = Path(base) / "raykit" / f"frozen-{digest.hexdigest()[:16]}.json"
        try:
            kept.parent.mkdir(parents=True, exist_ok=True)
            partial = kept.with_suffix(f".{os.getpid()}.tmp")  # whole, or not at all
            partial.write_text(json.dumps(found))
            partial.replace(kept)
            break
        except OSError:
            continue
    return found


def _frozen_modules() -> list[str]:
    """:func:`frozen_modules`, from the sources."""
    read = set(twin_table()["reference_modules"]())
    for source in sorted(COMPILED_SOURCE.glob("*.py")):
        read |= _modules_read(_parsed(source.read_bytes()))
    return sorted(read)


@functools.lru_cache(maxsize=256)
def _parsed(source: bytes) -> ast.Module:
    """A source file's syntax tree, parsed once per process for each content."""
    return ast.parse(source)


def _module_file(module: str) -> Path:
    """The source file of ``module``, a module of this copy of raykit (none is imported)."""
    path = COMPILED_SOURCE.parent.parent.joinpath(*module.split(".")[1:])
    return path / "__init__.py" if path.is_dir() else path.with_suffix(".py")


@functools.lru_cache(maxsize=256)
def _modules_read(tree: ast.Module) -> frozenset[str]:
    """The raykit modules (not the compiled engine's) whose globals a kernel module reads where
    numba freezes them: in the body of a kernel (a function under a decorator, ``@njit`` or
    ``@intrinsic``), or in the value of a top-level name a kernel reads (a constant computed at
    import). A name imported from a module that imports it in turn is followed to where it is
    defined."""
    imported: dict[str, tuple[str, str | None]] = {}  # local name: (module, its name there)
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and _ours(node.module):
            for alias in node.names:
                imported[alias.asname or alias.name] = (node.module, alias.name)
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if _ours(alias.name) and alias.asname:
                    imported[alias.asname] = (alias.name, None)
    kernels: list[ast.AST] = []
    constants: dict[str, ast.AST] = {}  # a top-level name: the value assigned to it
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.decorator_list:
            kernels += [*node.body, *node.args.defaults]
        elif isinstance(node, ast.Assign | ast.AnnAssign) and node.value is not None:
            for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                if isinstance(target, ast.Name):
                    constants[target.id] = node.value
    names = {n.id for part in kernels for n in ast.walk(part) if isinstance(n, ast.Name)}
    frozen = kernels + [constants[name] for name in names & constants.keys()]
    read: set[str] = set()
    for node in (inner for part in frozen for inner in ast.walk(part)):
        if isinstance(node, ast.Name) and node.id in imported:
            module, name = imported[node.id]
            read.add(_defined_in(module, name) if name else module)
    return frozenset(read)


def _ours(module: str | None) -> bool:
    """Whether ``module`` is raykit's, and not the compiled engine's (hashed whole already)."""
    return (
        bool(module)
        and (module + ".").startswith("raykit.")
        and not (module + ".").startswith("raykit.engine.compiled.")
    )


def _defined_in(module: str, name: str, depth: int = 0) -> str:
    """The module where ``name``, imported from ``module``, is defined: ``module``, unless it
    imports ``name`` from another of raykit's modules in turn."""
    path = _module_file(module)
    if depth > 8 or not path.exists():
        return module
    for node in _parsed(path.read_bytes()).body:
        if isinstance(node, ast.ImportFrom) and _ours(node.module):
            for alias in node.names:
                if (alias.asname or alias.name) == name:
                    return _defined_in(node.module, alias.name, depth + 1)
    return module


def cache_key() -> str:
    """A hash of everything the compiled kernels are made from: the compiled engine's sources
    (but the twin table, which no kernel reads), its folder, and the sources of
    :func:`frozen_modules`."""
    digest = hashlib.sha256(os.path.abspath(COMPILED_SOURCE).encode())
    for source in sorted(COMPILED_SOURCE.glob("*.py")):
        if source.name != "twins.py":  # read by no kernel: its modules count, below
            digest.update(source.name.encode() + b"\0" + source.read_bytes())
    for module in frozen_modules():
        digest.update(module.encode() + b"\0" + _module_file(module).read_bytes())
    return digest.hexdigest()[:16]


def cache_folder() -> Path | None:
    """Where numba keeps the compiled kernels: ``$RAYKIT_CACHE_DIR``, else ``$XDG_CACHE_HOME``
    or ``~/.cache``, else the temporary folder, under ``raykit/numba-<``:func:`cache_key```>``:
    the first of them that can be written, so a read-only install still caches. The key hashes
    the compiled engine's sources and the reference modules they repeat or read a constant of
    (numba freezes a global's value into the kernel), so editing any of them makes a new
    folder, and no kernel compiled from older source is ever loaded (numba checks a kernel's
    own file, not the files of the kernels it calls or the modules it reads). The folder
    counts too because numba keeps the kernels of each source folder apart: a second copy of
    raykit compiles its own, and must find no marker saying it need not
    (:func:`compiled_once`). None when no folder can be written (the kernels then compile in
    every process)."""
    key = cache_key()
    for base in _bases():
        folder = Path(base) / "raykit" / f"numba-{key}"
        try:
            folder.mkdir(parents=True, exist_ok=True)
            with tempfile.TemporaryFile(dir=folder):
                pass
        except OSError:
            continue
        return folder
    return None


def _bases() -> list[str]:
    """Where the caches may go, in order (:func:`cache_folder`)."""
    bases = [
        os.environ.get("RAYKIT_CACHE_DIR"),
        os.environ.get("XDG_CACHE_HOME"),
        os.path.join(os.path.expanduser("~"), ".cache"),
        os.path.join(tempfile.gettempdir(), f"raykit-{os.getuid()}"),
    ]
    return [base for base in bases if base]


def marker(entry: str, folder: Path | None = None) -> Path | None:
    """The file that says ``entry``'s kernels (:func:`entry_point`) are compiled and cached in
    ``folder`` (by default :func:`cache_folder`), which the compiled engine writes after the
    first render that needed them; None without a cache folder."""
    folder = cache_folder() if folder is None else folder
    return None if folder is None else folder / f"{entry}.ok"


def entry_point(scene: Scene) -> str:
    """The compiled engine's entry point that renders ``scene``: a scene with mirror rays'
    kernels, a lit scene's, or a flat one's only; a distributed scene's (stage 5) are its own:
    a moving scene's (motion blur), or a still one's, with mirror rays' kernels or without.
    Each compiles only what it renders."""
    mirrors = scene.max_depth > 0 and scene.materials.any_mirror
    if scene.distributed:
        if scene.moving:
            return "trace_moving"
        return "trace_sampled_mirrors" if mirrors else "trace_sampled"
    if not needs_shading(scene):
        return "trace_flat"
    return "trace_mirrors" if mirrors else "trace_lit"


def compiled_once(entry: str) -> bool:
    """Whether ``entry``'s kernels (:func:`marker`) are compiled and cached."""
    path = marker(entry)
    return path is not None and path.exists()


def numpy_seconds(scene: Scene, samples: int) -> float:
    """About how long the numpy engine takes to render ``scene`` with n x n samples (a
    distributed scene: with its own samples per pixel)."""
    camera = scene.camera
    if scene.distributed:
        rays = camera.width * camera.height * scene.sampling.samples_per_pixel
        return rays * NUMPY_SECONDS_PER_RAY["distributed"]
    rays = camera.width * camera.height * samples * samples
    return rays * NUMPY_SECONDS_PER_RAY["lit" if needs_shading(scene) else "flat"]


def compiled_refuses(scene: Scene) -> str | None:
    """What of distributed ray tracing in ``scene`` the compiled engine cannot render yet (no
    kernel repeats it), in words; None when it renders the whole scene. It renders all of stage
    5: area lights, a lens, glossy mirrors, render.samples_per_pixel > 1 with every sampler,
    and motion blur (every ray at its own time in the shutter interval), so None; kept for
    the one-line refusal of what a later stage adds before its kernels do."""
    del scene  # every scene renders
    return None


def refuse_distributed(scene: Scene) -> None:
    """A one-line ValueError naming what the compiled engine cannot render of ``scene``
    (:func:`compiled_refuses`)."""
    refused = compiled_refuses(scene)
    if refused is not None:
        raise ValueError(
            f"{scene.source}: the compiled engine does not render {refused} yet: use --engine numpy"
        )


def choose(engine: str, scene: Scene, samples: int = 1, dtype: type = np.float64) -> str:
    """``"numpy"`` or ``"compiled"``: the engine that renders, for ``engine`` in
    :data:`ENGINES` (see the module page). ValueError for an unknown name or a float32
    compiled render; :class:`EngineUnavailable` for ``"compiled"`` without numba."""
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {', '.join(ENGINES)}; got {engine!r}")
    if engine == "numpy":
        return "numpy"
    if engine == "compiled":
        if not compiled_available():
            raise EngineUnavailable(f"the compiled engine {compiled_missing()}")
        if dtype != np.float64:
            raise ValueError("the compiled engine renders in float64 only; use engine='numpy'")
        refuse_distributed(scene)
        return "compiled"
    if compiled_refuses(scene) is not None:
        return "numpy"
    if numpy_seconds(scene, samples) < AUTO_FROM or dtype != np.float64:
        return "numpy"  # before the cache's key, whose hash of the sources costs a little
    fast = compiled_available() and compiled_once(entry_point(scene))
    return "compiled" if fast else "numpy"

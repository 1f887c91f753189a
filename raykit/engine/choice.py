"""Which engine renders: the numpy one, or the compiled one (:mod:`raykit.engine.compiled`).

``engine="numpy"`` is the lecture's loop over numpy arrays (:func:`raykit.render.render`), and
always there. ``engine="compiled"`` needs numba (``pip install "raykit[fast]"``) and renders the
same bits in machine code. ``engine="auto"`` (the default) takes the compiled engine only when
the whole process is faster with it: numba is installed, the kernels the scene needs are
already compiled and cached (a first compile takes longer than most renders), the render is
float64, and the numpy engine would take longer than loading numba and the kernels costs
(``AUTO_FROM``, measured by ``raykit bench``). So a small render never pays for numba, and
nothing here imports it.
"""

from __future__ import annotations

import hashlib
import importlib.util
import os
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
# The numpy engine's time per ray, flat and shaded, and what loading numba and the cached
# kernels costs a process: measured on the 2-core machine by benchmarks/engines.py
# (`raykit bench` prints them again on yours)
NUMPY_SECONDS_PER_RAY = {"flat": 2.0e-7, "lit": 8.0e-7}
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


def cache_folder() -> Path | None:
    """Where numba keeps the compiled kernels: ``$RAYKIT_CACHE_DIR``, else ``$XDG_CACHE_HOME``
    or ``~/.cache``, else the temporary folder, under ``raykit/numba-<hash of the compiled
    engine's sources and its folder>``: the first of them that can be written, so a read-only
    install still caches. Editing a kernel makes a new folder, so no kernel compiled from older
    source is ever loaded (numba checks a kernel's own file, not the files of the kernels it
    calls). The folder counts too because numba keeps the kernels of each source folder apart:
    a second copy of raykit compiles its own, and must find no marker saying it need not
    (:func:`compiled_once`). None when no folder can be written (the kernels then compile in
    every process)."""
    digest = hashlib.sha256(os.path.abspath(COMPILED_SOURCE).encode())
    for source in sorted(COMPILED_SOURCE.glob("*.py")):
        digest.update(source.name.encode() + b"\0" + source.read_bytes())
    key = digest.hexdigest()[:16]
    bases = [
        os.environ.get("RAYKIT_CACHE_DIR"),
        os.environ.get("XDG_CACHE_HOME"),
        os.path.join(os.path.expanduser("~"), ".cache"),
        os.path.join(tempfile.gettempdir(), f"raykit-{os.getuid()}"),
    ]
    for base in filter(None, bases):
        folder = Path(base) / "raykit" / f"numba-{key}"
        try:
            folder.mkdir(parents=True, exist_ok=True)
            with tempfile.TemporaryFile(dir=folder):
                pass
        except OSError:
            continue
        return folder
    return None


def marker(entry: str, folder: Path | None = None) -> Path | None:
    """The file that says ``entry``'s kernels (:func:`entry_point`) are compiled and cached in
    ``folder`` (by default :func:`cache_folder`), which the compiled engine writes after the
    first render that needed them; None without a cache folder."""
    folder = cache_folder() if folder is None else folder
    return None if folder is None else folder / f"{entry}.ok"


def entry_point(scene: Scene) -> str:
    """The compiled engine's entry point that renders ``scene``: a scene with mirror rays'
    kernels, a lit scene's, or a flat one's only."""
    if not needs_shading(scene):
        return "trace_flat"
    return "trace_mirrors" if scene.max_depth > 0 and scene.materials.any_mirror else "trace_lit"


def compiled_once(entry: str) -> bool:
    """Whether ``entry``'s kernels (:func:`marker`) are compiled and cached."""
    path = marker(entry)
    return path is not None and path.exists()


def numpy_seconds(scene: Scene, samples: int) -> float:
    """About how long the numpy engine takes to render ``scene`` with n x n samples."""
    camera = scene.camera
    rays = camera.width * camera.height * samples * samples
    return rays * NUMPY_SECONDS_PER_RAY["lit" if needs_shading(scene) else "flat"]


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
        return "compiled"
    fast = compiled_available() and dtype == np.float64 and compiled_once(entry_point(scene))
    return "compiled" if fast and numpy_seconds(scene, samples) >= AUTO_FROM else "numpy"

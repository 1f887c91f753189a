"""The compiled engine's cache: its folder's key covers every source the kernels are made from,
the kernels' own and the reference modules they repeat or read a constant of."""

from __future__ import annotations

import ast
import dis
import inspect
import json
import os
import shutil
import subprocess
import sys
import types

import pytest

from conftest import REPO
from raykit.engine import choice

numba = pytest.importorskip("numba")
compiled = pytest.importorskip("raykit.engine.compiled")


def _kernels():
    """Every numba kernel of the compiled engine's modules, by ``module.name``."""
    found = {}
    for name, module in sorted(sys.modules.items()):
        if not name.startswith("raykit.engine.compiled.") or module is None:
            continue
        for attribute, value in vars(module).items():
            if getattr(value, "__module__", None) == name and _is_kernel(value):
                found[f"{name.rpartition('.')[2]}.{attribute}"] = value
    return found


def _is_kernel(value) -> bool:
    from numba.core.dispatcher import Dispatcher
    from numba.core.extending import _Intrinsic

    return isinstance(value, Dispatcher | _Intrinsic)


def _globals_read(function) -> set[str]:
    """The global names a function's bytecode loads, its nested functions' included."""
    names, codes = set(), [function.__code__]
    while codes:
        code = codes.pop()
        names |= {i.argval for i in dis.get_instructions(code) if i.opname == "LOAD_GLOBAL"}
        codes += [c for c in code.co_consts if isinstance(c, types.CodeType)]
    return names


def _defines(module, name: str) -> bool:
    """Whether ``module``'s own source assigns ``name`` at its top level."""
    tree = ast.parse(inspect.getsource(module))
    for node in tree.body:
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
        if any(isinstance(t, ast.Name) and t.id == name for t in targets):
            return True
    return False


def _home(name: str, value) -> set[str]:
    """The modules a global ``value`` read as ``name`` comes from: a module itself, a function's
    or class's module, or, for a constant, each raykit module that defines it."""
    if isinstance(value, types.ModuleType):
        return {value.__name__}
    if _is_kernel(value) or hasattr(value, "__module__") and not isinstance(value, int | float):
        function = getattr(value, "py_func", value)
        return {getattr(function, "__module__", None) or ""}
    return {
        module_name
        for module_name, module in list(sys.modules.items())
        if module_name.startswith("raykit.")
        and module is not None
        and vars(module).get(name) is value
        and _defines(module, name)
    }


def test_the_cache_key_holds_every_raykit_module_whose_globals_a_kernel_reads():
    kernels = _kernels()
    assert "spheres.hit_sphere" in kernels and "driver.lit_job" in kernels
    key = set(choice.frozen_modules())
    missing = {}
    for kernel_name, kernel in kernels.items():
        function = getattr(kernel, "py_func", None) or kernel._defn
        for name in _globals_read(function):
            if name not in function.__globals__:
                continue  # a builtin
            for home in _home(name, function.__globals__[name]):
                ours = home.startswith("raykit.") and not home.startswith("raykit.engine.compiled")
                if ours and home not in key:
                    missing.setdefault(kernel_name, set()).add(f"{home}.{name}")
    assert not missing, f"read by kernels but not in the cache's key: {missing}"
    assert "raykit.surfaces" in key  # OFFSET_FACTOR, read in surfaces, shadows, driver, ...


def test_the_cache_key_holds_the_modules_the_twins_repeat_and_no_python_side_import():
    key = choice.frozen_modules()
    for module in ("raykit.spheres", "raykit.shading", "raykit.mirrors", "raykit.render"):
        assert module in key
    # imported by the compiled engine only for Python-side work (prepare, annotations)
    for module in ("raykit.scene", "raykit.engine.adaptive", "raykit.engine.screen_bounds"):
        assert module not in key


def test_a_re_exported_constant_is_followed_to_the_module_that_defines_it(tmp_path, monkeypatch):
    package = tmp_path / "raykit"
    shutil.copytree(REPO / "raykit", package, ignore=shutil.ignore_patterns("__py*"))
    kernel = package / "engine/compiled/surfaces.py"
    kernel.write_text(
        kernel.read_text().replace("from raykit.surfaces import", "from raykit.render import")
    )
    render = package / "render.py"
    render.write_text(render.read_text() + "\nfrom raykit.surfaces import OFFSET_FACTOR\n")
    monkeypatch.setattr(choice, "COMPILED_SOURCE", package / "engine/compiled")
    assert choice._defined_in("raykit.render", "OFFSET_FACTOR") == "raykit.surfaces"
    assert "raykit.surfaces" in choice.frozen_modules()


# a kernel that reads OFFSET_FACTOR, called as the engine calls it, beside the reference's answer
START = """
import json, numpy as np
from raykit.engine import choice
from raykit.engine.compiled import surfaces
from raykit.surfaces import SurfacePoints
p, n, error = (0.5, -2.0, 3.0), (0.0, 0.6, 0.8), 1e-15
kernel = surfaces.start(*p, *n, error, *n)
reference = SurfacePoints(np.array([p]), np.array([n]), np.array([error])).start(np.array([n]))
print(json.dumps({"kernel": list(kernel), "reference": list(reference[0]),
                  "folder": str(choice.cache_folder()),
                  "hits": sum(surfaces.start.stats.cache_hits.values())}))
"""


def test_a_constant_edited_in_a_reference_module_gets_kernels_compiled_anew(tmp_path):
    """The edit keeps the file's size and time, which numba's own cache check would miss; and
    numba checks only the kernel's own file, which does not change."""
    shutil.copytree(REPO / "raykit", tmp_path / "raykit", ignore=shutil.ignore_patterns("__py*"))
    env = {**os.environ, "PYTHONPATH": str(tmp_path), "RAYKIT_CACHE_DIR": str(tmp_path / "c")}

    def run() -> dict:
        child = subprocess.run([sys.executable, "-c", START], cwd=tmp_path, env=env,
                               capture_output=True, text=True, timeout=600)  # fmt: skip
        assert child.returncode == 0, child.stderr
        return json.loads(child.stdout)

    first, warm = run(), run()
    assert first["kernel"] == first["reference"] and first["hits"] == 0
    assert warm == {**first, "hits": 1}  # served from the cache
    constants = tmp_path / "raykit/surfaces.py"
    stat, text = constants.stat(), constants.read_text()
    edited = text.replace("OFFSET_FACTOR = 16", "OFFSET_FACTOR = 64")
    assert edited != text and len(edited) == len(text)
    constants.write_text(edited)
    os.utime(constants, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    after = run()
    assert after["folder"] != first["folder"] and after["hits"] == 0  # compiled anew
    assert after["kernel"] == after["reference"] != first["reference"]

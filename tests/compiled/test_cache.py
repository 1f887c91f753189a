"""The compiled engine's cache: its folder's key covers every source the kernels are made from,
the kernels' own and the reference modules they repeat or read a constant of; an edited kernel
or constant is compiled again; a second copy of raykit gets its own folder; Ctrl-C leaves a
usable cache."""

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

from conftest import REPO, SCENES
from raykit.engine import choice
from raykit.io.scene_json import load_scene
from raykit.render import render

from .harness import (
    run_python,
)


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
    assert "spheres.hit_sphere" in kernels and "render.lit_job" in kernels
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
    assert "raykit.surfaces" in key  # OFFSET_FACTOR, read in surfaces, shadows, render, ...


def test_the_cache_key_holds_the_modules_the_twins_repeat_and_no_python_side_import():
    key = choice.frozen_modules()
    for module in ("raykit.spheres", "raykit.shading", "raykit.render"):
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


def test_cache_folder_is_keyed_on_the_engines_source(tmp_path, monkeypatch):
    import shutil

    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path))
    shutil.copytree(REPO / "raykit", tmp_path / "raykit", ignore=shutil.ignore_patterns("__py*"))
    package = tmp_path / "raykit/engine/compiled"
    monkeypatch.setattr(choice, "COMPILED_SOURCE", package)
    before = choice.cache_folder()
    source = package / "spheres.py"  # a kernel that the others call
    text = source.read_text()
    edited = text.replace("if not discriminant >= 0:", "if not discriminant >= 9:")
    assert edited != text
    source.write_text(edited)
    assert choice.cache_folder() != before
    assert choice.cache_folder().parent == before.parent == tmp_path / "raykit"


def test_a_second_copy_of_the_same_source_gets_its_own_cache_folder(tmp_path, monkeypatch):
    # numba keeps each source folder's kernels apart, so a second copy (another checkout, a
    # reinstall elsewhere) compiles again: it must say so, and auto must not count on a cache
    import shutil

    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    one, two = (tmp_path / copy / "raykit/engine/compiled" for copy in ("one", "two"))
    for package in (one, two):
        shutil.copytree(REPO / "raykit", package.parent.parent,
                        ignore=shutil.ignore_patterns("__py*"))  # fmt: skip
    monkeypatch.setattr(choice, "COMPILED_SOURCE", one)
    first = choice.cache_folder()
    choice.marker("trace_flat").write_text("20.0 s\n")  # as the first copy's first render leaves it
    assert choice.compiled_once("trace_flat")
    monkeypatch.setattr(choice, "COMPILED_SOURCE", two)
    assert choice.cache_folder() != first
    assert not choice.compiled_once("trace_flat")


def test_an_edited_kernel_is_compiled_again_not_served_from_the_cache(tmp_path):
    """The edit keeps the file's size and time, which numba's own cache check would miss."""
    import shutil

    shutil.copytree(REPO / "raykit", tmp_path / "raykit", ignore=shutil.ignore_patterns("__py*"))
    kernel = tmp_path / "raykit/engine/compiled/spheres.py"
    code = (
        "from raykit.io.scene_json import load_scene; from raykit.render import render\n"
        f"scene = load_scene({str(SCENES / 'classic.json')!r})\n"
        "print((render(scene, engine='compiled').object_index >= 0).sum())\n"
    )
    env = {"PYTHONPATH": str(tmp_path), "RAYKIT_CACHE_DIR": str(tmp_path / "cache")}
    first = run_python(code, cwd=tmp_path, **env)
    assert first.returncode == 0, first.stderr
    assert "compiling raykit's fast kernels, once" in first.stderr
    # the progress line names the kernels it compiles: a flat scene's, and no shading
    assert "trace_flat" in first.stderr and "light_lanes" not in first.stderr
    again = run_python(code, cwd=tmp_path, **env)
    assert "compiling" not in again.stderr and again.stdout == first.stdout  # served cached
    stat = kernel.stat()
    text = kernel.read_text()
    edited = text.replace("if not discriminant >= 0:", "if not discriminant >= 9:")
    assert edited != text and len(edited) == len(text)
    kernel.write_text(edited)
    os.utime(kernel, ns=(stat.st_atime_ns, stat.st_mtime_ns))
    third = run_python(code, cwd=tmp_path, **env)
    assert "compiling raykit's fast kernels, once" in third.stderr
    assert int(third.stdout) < int(first.stdout)  # the edit shows: fewer spheres are hit


def test_ctrl_c_during_the_first_compile_leaves_a_cache_the_next_run_renders_right_from(tmp_path):
    """numba writes each kernel's cache files whole; the marker comes only after a render."""
    import signal
    import threading
    import time

    from raykit.engine.compiled.compiling import MESSAGE

    code = (
        "from raykit.io.scene_json import load_scene; from raykit.render import render\n"
        f"scene = load_scene({str(SCENES / 'classic.json')!r})\n"
        "print((render(scene, engine='compiled').object_index >= 0).sum())\n"
    )
    cache = tmp_path / "cache"
    env = {**os.environ, "RAYKIT_CACHE_DIR": str(cache)}
    # Ctrl-C as in a terminal: a child started where SIGINT is ignored (a shell's background
    # job) would inherit that, and finish its compile
    child = subprocess.Popen(
        [sys.executable, "-c", code], cwd=REPO, env=env, stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )  # fmt: skip
    said = []  # its standard error, read as it comes (the progress line)
    reader = threading.Thread(target=lambda: said.extend(iter(child.stderr.readline, "")))
    reader.start()
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline and not (
        list(cache.rglob("*.nbi")) and MESSAGE in "".join(said)  # a kernel cached, and the
    ):  # progress line up: the entry point's compile is under way
        time.sleep(0.05)
    child.send_signal(signal.SIGINT)
    stdout = child.stdout.read()
    child.wait(timeout=300)
    reader.join()
    stderr = "".join(said)
    assert child.returncode != 0, f"the compile finished before it was interrupted: {stdout}"
    assert "KeyboardInterrupt" in stderr, (child.returncode, stdout, stderr[-2000:])
    assert list(cache.rglob("*.nbi")) and not list(cache.rglob("*.ok"))
    again = run_python(code, RAYKIT_CACHE_DIR=str(cache))
    assert again.returncode == 0, again.stderr
    assert "compiling raykit's fast kernels, once" in again.stderr  # what was not cached
    expected = (render(load_scene(SCENES / "classic.json")).object_index >= 0).sum()
    assert int(again.stdout) == expected
    assert [path.name for path in cache.rglob("*.ok")] == ["trace_flat.ok"]


def test_the_list_of_modules_read_is_kept_on_disk_until_a_source_changes(tmp_path, monkeypatch):
    shutil.copytree(REPO / "raykit", tmp_path / "raykit", ignore=shutil.ignore_patterns("__py*"))
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(choice, "COMPILED_SOURCE", tmp_path / "raykit/engine/compiled")
    found = choice.frozen_modules()
    assert list((tmp_path / "cache/raykit").glob("frozen-*.json"))

    def not_again():
        raise AssertionError("the sources read again, though none changed")

    monkeypatch.setattr(choice, "_frozen_modules", not_again)
    assert choice.frozen_modules() == found
    shading = tmp_path / "raykit/shading.py"
    shading.write_text(shading.read_text() + "\n")
    with pytest.raises(AssertionError, match="read again"):
        choice.frozen_modules()

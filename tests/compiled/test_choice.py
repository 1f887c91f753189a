"""Which engine renders (raykit.engine.choice) where numba is installed: auto, the command line's
refusal without numba, and small renders that never import it."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENES
from raykit.engine import choice
from raykit.io.scene_json import load_scene
from raykit.render import render

from .harness import (
    run_python,
)


def test_auto_keeps_small_renders_on_numpy_and_an_unknown_engine_is_refused():
    scene = load_scene(SCENES / "classic.json")
    assert choice.choose("auto", scene) == "numpy"  # numba's load would cost more than it saves
    assert choice.choose("compiled", scene) == "compiled"
    with pytest.raises(ValueError, match="engine must be one of auto, numpy, compiled"):
        render(scene, engine="fast")
    with pytest.raises(ValueError, match="float64 only"):
        render(scene, engine="compiled", dtype=np.float32)


def test_auto_takes_the_compiled_engine_for_large_work_once_it_is_compiled(monkeypatch):
    scene = load_scene(SCENES / "classic.json")
    big = replace(scene, camera=replace(scene.camera, width=1920, height=1080))
    monkeypatch.setattr(choice, "compiled_once", lambda entry: entry == "trace_flat")
    assert choice.choose("auto", big, samples=3) == "compiled"
    assert choice.choose("auto", big, samples=3, dtype=np.float32) == "numpy"
    lit = load_scene(SCENES / "classic_lit.json")
    lit = replace(lit, camera=replace(lit.camera, width=1920, height=1080))
    assert choice.choose("auto", lit, samples=3) == "numpy"  # its kernels are not compiled yet
    monkeypatch.setattr(choice, "compiled_once", lambda entry: False)  # a first compile costs more
    assert choice.choose("auto", big, samples=3) == "numpy"


def test_cli_refuses_the_compiled_engine_without_numba_in_one_line_naming_the_fix(tmp_path):
    out = tmp_path / "out.png"
    code = (
        "import sys, importlib.util as u\n"
        "find = u.find_spec\n"
        "u.find_spec = lambda name, *a: None if name == 'numba' else find(name, *a)\n"
        "from raykit.cli import main\n"
        f"sys.exit(main(['render', 'scenes/classic.json', '-o', {str(out)!r}, "
        "'--engine', 'compiled']))"
    )
    run = run_python(code)
    assert run.returncode == 2
    assert run.stderr.strip().splitlines() == [
        "raykit: error: --engine compiled needs numba, which is not installed: "
        'pip install "raykit[fast]"'
    ]
    assert not out.exists()
    unknown = run_python(
        "import sys; from raykit.cli import main; "
        f"sys.exit(main(['render', 'scenes/classic.json', '-o', {str(out)!r}, '--engine', 'gpu']))"
    )
    assert unknown.returncode == 2 and "invalid choice: 'gpu'" in unknown.stderr


def test_small_renders_never_import_numba():
    run = run_python(
        "import sys\n"
        "from raykit.io.scene_json import load_scene\n"
        "from raykit.render import render\n"
        "render(load_scene('scenes/classic.json'))\n"
        "assert 'numba' not in sys.modules, 'numba was imported'\n"
    )
    assert run.returncode == 0, run.stderr


def test_auto_judges_a_distributed_scene_by_its_sample_rays_and_its_own_kernels(monkeypatch):
    scene = load_scene(SCENES / "soft_shadows.json")  # 320 x 240, 16 samples per pixel
    small = replace(scene, camera=replace(scene.camera, width=32, height=24))
    monkeypatch.setattr(choice, "compiled_once", lambda entry: entry == "trace_sampled")
    assert choice.entry_point(scene) == "trace_sampled"
    rays = 320 * 240 * 16
    assert choice.numpy_seconds(scene, 1) == rays * choice.NUMPY_SECONDS_PER_RAY["distributed"]
    assert choice.choose("auto", scene) == "compiled"
    assert choice.choose("auto", small) == "numpy"  # numba's load would cost more than it saves
    moving = load_scene(SCENES / "motion_blur.json")
    assert choice.numpy_seconds(moving, 1) >= choice.AUTO_FROM
    assert choice.choose("auto", moving) == "compiled"  # a distributed scene like any other
    monkeypatch.setattr(choice, "compiled_once", lambda entry: entry != "trace_sampled")
    assert choice.choose("auto", scene) == "numpy"  # its kernels are not compiled yet

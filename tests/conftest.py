"""Shared helpers: small scenes built in code, and the repository's folders."""

from __future__ import annotations

import copy
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "scenes"


def scene_dict(**overrides) -> dict:
    """A minimal valid v1 scene (one sphere at the origin, seen from +z), with overrides."""
    scene = {
        "camera": {
            "eye": [0, 0, 5],
            "lookat": [0, 0, 0],
            "up": [0, 1, 0],
            "fov_angle": 45,
            "width": 32,
            "height": 24,
        },
        "spheres": [{"center": [0, 0, 0], "radius": 1, "color": [1, 0, 0]}],
    }
    scene.update(copy.deepcopy(overrides))
    return scene


def set_field(path: str, value):
    """A scene mutation that sets the field at a dotted path (list indices as numbers)."""

    def mutate(scene: dict) -> None:
        *parents, last = [int(k) if k.isdigit() else k for k in path.split(".")]
        node = scene
        for key in parents:
            node = node[key]
        node[last] = value

    return mutate


def delete_field(path: str):
    """A scene mutation that deletes the field at a dotted path."""

    def mutate(scene: dict) -> None:
        *parents, last = [int(k) if k.isdigit() else k for k in path.split(".")]
        node = scene
        for key in parents:
            node = node[key]
        del node[last]

    return mutate


@pytest.fixture
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def child_python(tmp_path_factory) -> str:
    """A Python for graded submissions. As root the grader runs them as an unprivileged user,
    who cannot run an interpreter under /root: then a venv of the system Python with numpy and
    Pillow is made once (as Gradescope's setup.sh does) and kept in /tmp between runs."""
    import os
    import subprocess
    import sys

    if os.geteuid() != 0:
        return sys.executable
    venv = Path("/tmp/raykit-sandbox-python")
    python = venv / "bin" / "python"
    if not python.exists():
        system = Path("/usr/bin/python3")
        if not system.exists():
            pytest.skip("as root, grading needs /usr/bin/python3 for the sandbox user")
        made = subprocess.run([str(system), "-m", "venv", str(venv)], capture_output=True)
        pip = (
            subprocess.run(
                [str(venv / "bin/pip"), "install", "-q", "numpy", "Pillow"], capture_output=True
            )
            if made.returncode == 0
            else made
        )
        if pip.returncode != 0:
            pytest.skip(f"cannot make the sandbox Python: {pip.stderr.decode()[-300:]}")
        subprocess.run(["chmod", "-R", "a+rX", str(venv)], check=True)
    return str(python)

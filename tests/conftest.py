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

"""What raykit computes from its committed inputs, written to one ``.npz`` for comparison across
kinds of processor (``tests/test_machine_independent.py`` runs it under several).

    python tests/support/machine_outputs.py OUT.npz

It holds the sphereflake scene the gallery writes, every example scene rendered small by the
numpy engine, a forward (photon) render and every line-scan sweep.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
SMALL = 0.25  # of each example scene's width and height: the same rays' arithmetic, fewer rays


def _module(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _small(scene, width: int, height: int):
    return replace(scene, camera=replace(scene.camera, width=width, height=height))


def outputs() -> dict[str, np.ndarray]:
    """Name -> array for everything compared; lit pictures are named ``lit:…`` (see the test)."""
    from raykit.forward import forward_render
    from raykit.io.linescan_json import load_line_scene
    from raykit.io.scene_json import load_scene
    from raykit.linescan.scan import sweep
    from raykit.render import render
    from raykit.shading import needs_shading

    found: dict[str, np.ndarray] = {}
    sphereflake = json.dumps(_module(REPO / "docs/make_gallery.py").sphereflake_lit())
    found["flat:sphereflake_lit.json"] = np.frombuffer(sphereflake.encode(), dtype=np.uint8)
    for path in sorted((REPO / "scenes").glob("*.json")):
        scene = load_scene(path)
        width, height = (
            max(8, round(n * SMALL)) for n in (scene.camera.width, scene.camera.height)
        )
        image = render(_small(scene, width, height), engine="numpy")
        kind = "lit" if needs_shading(scene) else "flat"
        found[f"{kind}:{path.stem}.rgb"] = image.rgb
        found[f"{kind}:{path.stem}.t"] = image.t
    lit = load_scene(REPO / "scenes/shadow_on_billboard.json")
    found["flat:forward.rgb"], _ = forward_render(_small(lit, 64, 48), 20_000, seed=1)
    for path in sorted((REPO / "scenes/linescan").glob("*.json")):
        found[f"flat:linescan_{path.stem}"] = sweep(load_line_scene(path)).image
    return found


if __name__ == "__main__":
    np.savez(sys.argv[1], **outputs())

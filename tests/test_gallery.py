"""docs/gallery.md shows every picture docs/make_gallery.py makes, each with its scene file and
command, and each picture committed is what its command makes today (the pictures themselves
are made by ``python docs/make_gallery.py``)."""

import importlib.util
import json
import os
import shlex

import numpy as np
import pytest
from PIL import Image

from conftest import REPO

REDUCED = 4  # the gallery's renders are remade this many times narrower, in seconds


def _gallery():
    spec = importlib.util.spec_from_file_location("make_gallery", REPO / "docs/make_gallery.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_gallery_page_shows_each_picture_with_its_scene_file_and_command():
    gallery = _gallery()
    page = (REPO / "docs/gallery.md").read_text()
    for _, scene, command, _ in gallery.ENTRIES:
        args = shlex.split(command)
        picture = args[args.index("-o") + 1].replace("{out}/", "")
        assert args[1] == scene and (REPO / scene).exists(), scene
        assert (REPO / "docs/gallery" / picture).exists(), picture
        assert f"](gallery/{picture})" in page and f"`{scene}`" in page
        assert "raykit " + command.replace("{out}", "docs/gallery") in page


def test_gallery_sphereflake_file_is_what_the_script_writes():
    written = json.loads((REPO / "docs/gallery/sphereflake_lit.json").read_text())
    assert written == json.loads(json.dumps(_gallery().sphereflake_lit()))
    assert len(written["spheres"]) == 820 and written["lights"]


def _rms(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean((a - b) ** 2)))


@pytest.mark.parametrize("entry", range(len(_gallery().ENTRIES)))
def test_each_gallery_picture_is_what_its_command_makes(entry, tmp_path, monkeypatch):
    """A render is remade REDUCED times narrower (``--width``: the same view) and the committed
    picture, scaled down to it, must differ from it less than it differs from itself moved one
    pixel sideways: sampling noise and edges passes, a moved, changed or other scene does not.
    A sweep, which has no width, is docs/images' picture of the same command, byte for byte
    (tests/test_reproducible.py remakes that one)."""
    from raykit.cli import main

    _, _, command, _ = _gallery().ENTRIES[entry]
    args = shlex.split(command.format(out=tmp_path))
    name = os.path.basename(args[args.index("-o") + 1])
    committed = REPO / "docs/gallery" / name
    if "--width" not in args:
        assert committed.read_bytes() == (REPO / "docs/images" / name).read_bytes(), name
        return
    width = args.index("--width") + 1
    args[width] = str(int(args[width]) // REDUCED)
    monkeypatch.chdir(REPO)  # the commands' scene paths are the repository's
    assert main(args) == 0
    fresh = np.asarray(Image.open(tmp_path / name).convert("RGB"), float)
    pinned = Image.open(committed).convert("RGB").resize(fresh.shape[1::-1], Image.BOX)
    pinned = np.asarray(pinned, float)
    moved = _rms(pinned[:, 1:], pinned[:, :-1])
    assert _rms(fresh, pinned) < moved, (name, _rms(fresh, pinned), moved)

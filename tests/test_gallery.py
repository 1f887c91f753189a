"""docs/gallery.md shows every picture docs/make_gallery.py makes, each with its scene file and
command (the pictures themselves are made by ``python docs/make_gallery.py``, about 20 s)."""

import importlib.util
import json
import shlex

from conftest import REPO


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

"""docs/slide_pixel_formula.py renders with the slide's second pixel formula patched into the
renderer: each pixel's ray goes through the point that way of fitting N + 1 positions to N
pixels gives it, not through its centre (the measurement itself, about 15 s, is run by hand)."""

import importlib.util
from dataclasses import replace

import numpy as np
import pytest

from conftest import REPO, SCENES
from raykit.camera import rays_through
from raykit.io.scene_json import load_scene
from raykit.render import cast, render


def _script():
    path = REPO / "docs/slide_pixel_formula.py"
    spec = importlib.util.spec_from_file_location("slide_pixel_formula", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize(("variant", "spread"), [("first N", False), ("spread", True)])
def test_patched_render_casts_each_pixels_ray_through_the_slides_position(variant, spread):
    classic = load_scene(SCENES / "classic.json")
    width, height = 32, 24
    scene = replace(classic, camera=replace(classic.camera, width=width, height=height))
    with _script().slide_formula(variant, width, height):
        got = render(scene, skip_hidden=False, engine="numpy").object_index
    rows, cols = np.divmod(np.arange(width * height), width)
    x, y = cols.astype(float), rows.astype(float)  # the pixel's corner: u = -1 + c·2/N
    if spread:  # all N + 1 spread over the N pixels: from -1 to 1, both included
        x, y = x * width / (width - 1), y * height / (height - 1)
    origins, directions = rays_through(scene.camera, x, y)
    expected = cast(scene, origins, directions).index.reshape(height, width)
    assert np.array_equal(got, expected)
    centres = render(scene, skip_hidden=False, engine="numpy").object_index
    assert (got != centres).any()  # the patch changed what the pixels see

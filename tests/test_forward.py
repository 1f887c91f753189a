"""Forward light tracing converges to the backward render of the same diffuse term."""

from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENES
from raykit.forward import diffuse_only, forward_render
from raykit.io.scene_json import load_scene
from raykit.render import render


def _small(name: str, width: int = 40, height: int = 30):
    scene = load_scene(SCENES / f"{name}.json")
    return replace(scene, camera=replace(scene.camera, width=width, height=height))


@pytest.mark.slow
def test_forward_error_falls_within_its_monte_carlo_standard_error_as_photons_grow():
    """Eight seeded runs per photon count give each pixel's mean and its standard error; the
    mean's distance from the backward render must stay within 2 RMS standard errors (plus the
    backward image's own sampling error, from 8 x 8 against 16 x 16 samples per pixel), and
    shrink as the photons grow."""
    scene = _small("shadow_on_billboard")
    backward = render(diffuse_only(scene), samples=16).rgb
    backward_error = np.sqrt(np.mean((render(diffuse_only(scene), samples=8).rgb - backward) ** 2))
    errors = []
    for photons in (25_000, 100_000, 400_000):
        runs = np.stack([forward_render(scene, photons, seed=s)[0] for s in range(8)])
        mean = runs.mean(axis=0)
        standard_error = runs.std(axis=0, ddof=1) / np.sqrt(len(runs))
        error = np.sqrt(np.mean((mean - backward) ** 2))
        bound = 2 * np.sqrt(np.mean(standard_error**2)) + backward_error
        assert error <= bound, (photons, error, bound)
        errors.append(error)
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 0.5 * errors[0]  # 16 times the photons: about a quarter of the error


def test_forward_render_is_seeded():
    scene = _small("shadow_on_billboard", 16, 12)
    first, _ = forward_render(scene, 20_000, seed=3)
    again, _ = forward_render(scene, 20_000, seed=3)
    other, _ = forward_render(scene, 20_000, seed=4)
    assert (first == again).all() and not (first == other).all()


def test_most_photons_never_reach_the_image():
    scene = _small("shadow_on_billboard")
    _, stats = forward_render(scene, 50_000, seed=1)
    assert stats.emitted == 50_000 * len(scene.lights)
    assert stats.landed < stats.hit < stats.emitted
    assert stats.through_hole < 1e-4 * stats.emitted  # a 1 mm pinhole: almost none


def test_forward_tracing_needs_point_lights():
    scene = load_scene(SCENES / "classic_lit.json")  # a sun and a lamp: no place for the sun's
    with pytest.raises(ValueError, match="point lights"):
        diffuse_only(scene)

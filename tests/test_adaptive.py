import numpy as np
import pytest

from conftest import SCENES
from raykit.engine.adaptive import edge_pixels
from raykit.io.scene_json import load_scene
from raykit.render import render


@pytest.mark.parametrize(
    "name",
    [
        "classic",
        pytest.param("cutouts", marks=pytest.mark.slow),
        pytest.param("wide_fov", marks=pytest.mark.slow),
    ],
)
def test_adaptive_supersampling_matches_full_supersampling(name):
    scene = load_scene(SCENES / f"{name}.json")
    full, adaptive = render(scene, 3), render(scene, 3, adaptive=True)
    same = np.all(np.abs(full.rgb - adaptive.rgb) <= 1e-12, axis=-1)  # n*n*c/(n*n) vs c
    assert same.mean() >= 0.999
    reference = render(scene, 6).rgb
    error = lambda image: np.sqrt(np.mean((image - reference) ** 2))  # noqa: E731
    assert error(adaptive.rgb) <= 1.01 * error(full.rgb)
    assert np.array_equal(full.object_index, adaptive.object_index)


@pytest.mark.parametrize("samples", [2, 3])
def test_edge_pixels_get_exactly_the_full_renders_colour(samples):
    # refine casts all samples of a tile at once; they must still be summed in the full
    # render's order, so an edge pixel's colour is the same bits either way
    scene = load_scene(SCENES / "cutouts.json")
    first = render(scene)
    edge = edge_pixels(first.rgb, first.object_index)
    full, adaptive = render(scene, samples), render(scene, samples, adaptive=True)
    assert edge.mean() > 0.02
    assert np.array_equal(full.rgb[edge], adaptive.rgb[edge])


def test_only_pixels_next_to_another_colour_or_object_are_edges():
    rgb = np.zeros((5, 6, 3))
    rgb[:, 3:] = 1.0
    index = np.zeros((5, 6), dtype=int)
    index[0, 0] = 1  # another object of the same colour
    edge = edge_pixels(rgb, index)
    assert edge[:, 2:4].all() and not edge[:, 5].any()
    assert edge[0, 0] and edge[1, 1] and not edge[3, 0]

"""Glossy reflection (FOCG 13.4.4): the mirror's reflected ray perturbed within the square of side
a; a = 0 is the ideal mirror to the byte; a ray perturbed below the surface is absorbed; the
perturbations average out to the mirror's direction; the same seed gives the same bytes; the
compiled engine refuses a glossy scene. Seeded throughout."""

import json
from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENES
from raykit.billboards import Billboard
from raykit.camera import Camera
from raykit.engine.choice import choose, compiled_available
from raykit.io.scene_json import scene_from_dict
from raykit.materials import Material
from raykit.mirrors import glossy_reflect, reflect
from raykit.rays import dot, normalize
from raykit.render import cast, render, secondary_caster
from raykit.sampling import Sampling, jittered_set, perturbed_direction
from raykit.scene import Scene
from raykit.shading import shade


def _small(name: str, glossiness: float | None = None, **render_settings) -> Scene:
    """The scene ``name`` at 40 x 28 with its render settings changed, and (``glossiness``) its
    first sphere's glossiness."""
    data = json.loads((SCENES / name).read_text())
    data["camera"].update(width=40, height=28)
    data["render"].update(render_settings)
    if glossiness is not None:
        data["spheres"][0]["glossiness"] = glossiness
    return scene_from_dict(data, source=name, folder=SCENES)


def test_a_glossy_direction_is_the_mirror_direction_moved_in_the_square_by_the_numbers():
    # d straight down onto the floor: r = (0, 1, 0), whose basis is u = (0, 0, 1), v = (1, 0, 0)
    d, n = np.array([[0.0, -1, 0]]), np.array([[0.0, 1, 0]])
    r_prime, above = glossy_reflect(d, n, np.array([0.5]), np.array([[0.75, 0.25]]))
    # u' = -a/2 + ξ1·a = 0.125, v' = -a/2 + ξ2·a = -0.125
    assert r_prime.tolist() == normalize(np.array([[-0.125, 1.0, 0.125]])).tolist()
    assert above.tolist() == [True]


def test_the_glossy_offset_is_perpendicular_to_the_mirror_direction_and_as_long_as_u_v():
    # r' = normalize(r + u'·u + v'·v): scaled back to r'·r = 1, r' - r is the offset u'·u + v'·v,
    # perpendicular to r and of length √(u'² + v'²) only in an orthonormal basis around r
    rng = np.random.default_rng(13)
    d, n = normalize(rng.normal(size=(300, 3))), normalize(rng.normal(size=(300, 3)))
    numbers, a = rng.random((300, 2)), 0.6
    r = reflect(d, n)
    r_prime, _ = glossy_reflect(d, n, np.full(300, a), numbers)
    offset = r_prime / dot(r_prime, r)[:, None] - r
    along = -a / 2 + numbers * a  # (u', v')
    assert np.abs(dot(offset, r)).max() < 1e-12
    assert np.allclose(dot(offset, offset), dot(along, along), rtol=1e-9, atol=1e-15)


def test_glossiness_zero_is_the_ideal_mirror_bit_for_bit():
    rng = np.random.default_rng(44)
    d, n = normalize(rng.normal(size=(200, 3))), normalize(rng.normal(size=(200, 3)))
    r_prime, above = glossy_reflect(d, n, np.zeros(200), rng.random((200, 2)))
    assert r_prime.tobytes() == reflect(d, n).tobytes() and above.all()


def test_a_mirror_of_glossiness_zero_renders_the_ideal_mirrors_bytes():
    data = json.loads((SCENES / "mirror_balls.json").read_text())
    data["camera"].update(width=40, height=25)
    data.update(version=2, render={"samples_per_pixel": 4, "seed": 3})
    ideal = render(scene_from_dict(data, folder=SCENES), engine="numpy")
    for sphere in data["spheres"]:
        sphere["glossiness"] = 0
    zero = render(scene_from_dict(data, folder=SCENES), engine="numpy")
    assert zero.rgb.tobytes() == ideal.rgb.tobytes()


def _grazing_floor_scene(glossiness: float, mirror: float) -> Scene:
    """An unlit floor mirror (y = 0) of colour 0.2 under a sky of (0.5, 0.6, 0.9)."""
    floor = Billboard(
        np.array([-50.0, 0, -50]), np.array([-50.0, 0, 50]), np.array([50.0, 0, -50]),
        np.full(3, 0.2), material=Material(mirror=np.full(3, mirror), glossiness=glossiness),
    )  # fmt: skip
    camera = Camera(np.array([0.0, 5, 5]), np.zeros(3), np.array([0.0, 1, 0]), 40, 4, 4)
    return Scene(camera, (), (floor,), np.array([0.5, 0.6, 0.9]), max_depth=1)


def test_a_ray_perturbed_below_the_surface_is_absorbed_and_the_mirror_adds_black():
    # a ray grazing the floor: with a = 2, ξ1 = 0 tilts its reflection below the floor, ξ1 = 0.99
    # above it (u, the basis vector along ξ1, points nearly straight up for this r)
    origins = np.array([[-10.0, 0.5, 0.0]] * 2)
    directions = normalize(np.array([[1.0, -0.05, 0.0]] * 2))
    numbers = np.array([[0.0, 0.5], [0.99, 0.5]])
    _, above = glossy_reflect(directions, np.array([[0.0, 1, 0]] * 2), np.full(2, 2.0), numbers)
    assert above.tolist() == [False, True]
    scene = _grazing_floor_scene(2.0, 0.5)
    hits = cast(scene, origins, directions)
    colors = shade(scene, secondary_caster(scene), origins, directions, hits,
                   gloss_uniforms=numbers[:, None, :])  # fmt: skip
    assert colors[0].tolist() == [0.2, 0.2, 0.2]  # absorbed: the floor's own colour only
    assert colors[1].tolist() == (0.2 + 0.5 * np.array([0.5, 0.6, 0.9])).tolist()  # the sky


def test_the_mean_of_glossy_directions_approaches_the_mirror_direction():
    rng = np.random.default_rng(7)
    r = normalize(rng.normal(size=(1, 3)))
    errors = []
    for n in (4, 16, 64):
        numbers = jittered_set(n, rng.random((n * n, 2)))
        mean = perturbed_direction(np.repeat(r, n * n, axis=0), 0.5, numbers).mean(axis=0)
        errors.append(float(np.arccos(min(1.0, dot(normalize(mean[None]), r)[0]))))
    assert errors[2] < errors[0] and errors[2] < 1e-3


def test_a_faintly_glossy_mirror_renders_as_the_ideal_one():
    faint = _small("glossy.json", 1e-9, samples_per_pixel=4)
    ideal = render(_small("glossy.json", 0, samples_per_pixel=4), engine="numpy").rgb
    assert faint.materials.any_glossy
    assert np.abs(render(faint, engine="numpy").rgb - ideal).max() < 1e-6


def test_the_glossy_mirror_blurs_what_the_ideal_one_shows_sharp():
    glossy = render(_small("glossy.json", samples_per_pixel=16), engine="numpy").rgb
    ideal = render(_small("glossy.json", 0, samples_per_pixel=16), engine="numpy").rgb
    # the glossy sphere (left half) differs from the ideal one; the pixels that see only the
    # ideal sphere, the floor and the sky (far right) are the same bytes: the new numbers come
    # after the old ones, which keep theirs
    assert np.abs(glossy[:, :18] - ideal[:, :18]).max() > 0.05
    assert glossy[:, 30:].tobytes() == ideal[:, 30:].tobytes()


@pytest.mark.parametrize("sampler", ["random", "jittered", "sobol"])
def test_a_glossy_render_is_the_same_bytes_for_the_same_seed_whatever_the_tiles(sampler):
    scene = _small("glossy.json", samples_per_pixel=4, sampler=sampler)
    first = render(scene, engine="numpy").rgb
    assert first.tobytes() == render(scene, engine="numpy", skip_hidden=False).rgb.tobytes()
    other = replace(scene, sampling=Sampling(4, sampler, 2))
    assert first.tobytes() != render(other, engine="numpy").rgb.tobytes()


def test_the_compiled_engine_takes_a_glossy_scene_and_auto_keeps_a_small_one_on_numpy():
    # the engines' bytes compared: tests/compiled/test_render.py
    scene = _small("glossy.json", samples_per_pixel=1)  # one sample: distributed by the gloss
    assert scene.distributed and choose("auto", scene) == "numpy"
    if not compiled_available():
        pytest.skip("numba is not installed")
    assert choose("compiled", scene) == "compiled"

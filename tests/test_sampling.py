"""The sample patterns (raykit.sampling), exactly on given uniform numbers, and the render's
noise (raykit.engine.noise): repeatable from its counter, whatever the order it is asked in,
and uniform (seeded tests)."""

import math
import subprocess
import sys
from fractions import Fraction

import numpy as np
import pytest
from scipy import stats

from conftest import REPO
from raykit.engine.noise import Dimensions, PixelSamples, counter_hash, shuffle, uniforms
from raykit.rays import dot, length
from raykit.sampling import (
    Sampling,
    _cos_sin,
    basis_around,
    jittered_point,
    jittered_set,
    owen_scramble,
    perturbed_direction,
    point_in_pixel,
    point_on_disk,
    point_on_lens,
    point_on_parallelogram,
    random_set,
    reverse_bits,
    shutter_times,
    sobol_points,
    sobol_set,
)

XI = np.array([[0.0, 0.0], [0.25, 0.5], [0.5, 0.5], [0.75, 0.125], [0.999, 0.001]])


def test_a_point_in_a_pixel_is_its_corner_plus_the_two_numbers():
    x, y = point_in_pixel(np.array([0, 3]), np.array([5, 7]), np.array([[0.25, 0.5], [0, 0.75]]))
    assert x.tolist() == [5.25, 7.0] and y.tolist() == [0.5, 3.75]


def test_the_random_set_is_the_numbers_themselves():
    assert np.array_equal(random_set(XI), XI)


def test_the_jittered_set_puts_sample_k_in_cell_k_at_its_jitter():
    xi = np.array([[0.5, 0.5], [0.0, 0.0], [0.5, 0.25], [0.75, 0.75]])
    assert jittered_set(2, xi).tolist() == [[0.25, 0.25], [0.5, 0.0], [0.25, 0.625], [0.875, 0.875]]
    assert jittered_point(np.array([5]), 3, np.array([[0.5, 0.5]])).tolist() == [[2.5 / 3, 0.5]]


@pytest.mark.parametrize("n", [1, 2, 3, 4, 7])
def test_a_jittered_set_has_exactly_one_sample_in_each_cell(n):
    points = jittered_set(n, np.random.default_rng(n).random((n * n, 2)))
    cells = np.floor(points * n).astype(int)
    assert sorted(map(tuple, cells)) == [(i, j) for i in range(n) for j in range(n)]


def test_a_jittered_set_refuses_a_count_that_is_not_n_squared():
    with pytest.raises(ValueError, match="3 x 3"):
        jittered_set(3, np.zeros((8, 2)))


def test_a_point_on_the_parallelogram_is_corner_plus_xi_times_the_edges():
    corner, a, b = np.array([1.0, 2, 3]), np.array([2.0, 0, 0]), np.array([0.0, 0, 4])
    points = point_on_parallelogram(corner, a, b, XI[:3])
    assert points.tolist() == [[1, 2, 3], [1.5, 2, 5], [2, 2, 5]]


def test_the_concentric_map_gives_exact_points_on_the_axes_and_diagonals():
    xi = np.array([[0.5, 0.5], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5], [0.5, 0.0], [1.0, 1.0]])
    disk = point_on_disk(xi)
    h = math.sqrt(0.5)
    expected = [[0, 0], [1, 0], [0, 1], [-1, 0], [0, -1], [h, h]]
    assert np.allclose(disk, expected, atol=1e-15)
    assert disk[0].tolist() == [0.0, 0.0]  # the centre: no 0/0


def _exact_cos_sin(angle: float) -> tuple[float, float]:
    """cos and sin of a float64 angle, rounded once from their Taylor series in exact rationals
    (to x^59: far below half an ulp for |angle| <= pi/4)."""
    x = Fraction(angle)
    cos, sin, term = Fraction(0), Fraction(0), Fraction(1)
    for i in range(60):
        if i % 2 == 0:
            cos += term * (-1) ** (i // 2)
        else:
            sin += term * (-1) ** (i // 2)
        term = term * x / (i + 1)
    return float(cos), float(sin)


def test_the_concentric_maps_cosine_and_sine_are_within_an_ulp_of_the_exact_ones():
    rng = np.random.default_rng(57)
    angle = np.concatenate([rng.uniform(-math.pi / 4, math.pi / 4, 400),
                            [-math.pi / 4, math.pi / 4, 1e-300, -1e-8, 0.5]])  # fmt: skip
    cos, sin = _cos_sin(angle)
    exact = np.array([_exact_cos_sin(float(a)) for a in angle])
    for got, want in ((cos, exact[:, 0]), (sin, exact[:, 1])):  # an ulp of the smaller: just
        ulp = np.spacing(np.minimum(np.abs(got), np.abs(want)))  # under 1, half that above
        assert np.all(np.abs(got - want) <= ulp)


def test_the_concentric_map_stays_in_the_disk_and_keeps_area():
    rng = np.random.default_rng(44)
    xi = rng.random((20000, 2))
    disk = point_on_disk(xi)
    assert (length(disk) <= 1.0 + 1e-15).all()
    # area: the Jacobian's determinant is pi everywhere (the unit square onto the disk of area pi)
    h = 1e-6
    inner = xi[(np.abs(xi - 0.5) > 0.01).all(axis=1)][:2000]  # away from the diagonals' kinks
    inner = inner[np.abs(np.abs(inner[:, 0] - 0.5) - np.abs(inner[:, 1] - 0.5)) > 0.01]
    dx = (point_on_disk(inner + [h, 0]) - point_on_disk(inner - [h, 0])) / (2 * h)
    dy = (point_on_disk(inner + [0, h]) - point_on_disk(inner - [0, h])) / (2 * h)
    det = dx[:, 0] * dy[:, 1] - dx[:, 1] * dy[:, 0]
    assert np.allclose(np.abs(det), math.pi, rtol=1e-5)
    # so a radius below r holds r^2 of the points (square ring max(|a|,|b|) < r: exactly r^2)
    grid = (np.stack(np.meshgrid(np.arange(100), np.arange(100)), -1).reshape(-1, 2) + 0.5) / 100
    assert (length(point_on_disk(grid)) < 0.5).mean() == 0.25


def test_the_lens_has_radius_half_the_aperture_not_the_aperture():
    u, v = np.array([1.0, 0, 0]), np.array([0.0, 1, 0])
    edge = point_on_lens(np.array([0.0, 0, 5]), u, v, 2.0, np.array([[1.0, 0.5], [0.5, 0.5]]))
    assert edge.tolist() == [[1.0, 0.0, 5.0], [0.0, 0.0, 5.0]]  # aperture 2: radius 1


def test_the_basis_around_a_direction_is_orthonormal_right_handed_with_w_along_it():
    r = np.random.default_rng(3).normal(size=(500, 3))
    r = np.vstack([r, [[0, 0, 1], [1, 0, 0], [0, -2, 0], [1, 1, 1]]])
    u, v, w = basis_around(r)
    for a, b in ((u, v), (v, w), (w, u)):
        assert np.allclose(dot(a, b), 0, atol=1e-12)
    for a in (u, v, w):
        assert np.allclose(length(a), 1)
    assert np.allclose(np.cross(u, v), w) and np.allclose(w * length(r)[:, None], r)


def test_the_perturbed_direction_moves_r_within_the_square_of_side_a():
    r = np.array([[0.0, 0, 1], [0.0, 0, 1]])
    centre, corner = perturbed_direction(r, 0.4, np.array([[0.5, 0.5], [1.0, 1.0]]))
    assert centre.tolist() == [0.0, 0.0, 1.0]
    u, v, _ = basis_around(r[:1])
    expected = r[0] + 0.2 * u[0] + 0.2 * v[0]
    assert np.allclose(corner, expected / np.sqrt(dot(expected, expected)))
    assert perturbed_direction(r, 0.0, np.array([[0.9, 0.1], [0.3, 0.7]])).tolist() == r.tolist()


def _elementary_cells(points: np.ndarray, m: int) -> list[int]:
    """For each split of 2^m into 2^a columns by 2^(m-a) rows, how many of those cells hold a
    point of ``points (N, 2)``: 2^m for every a, where they are a (0, m, 2)-net."""
    found = []
    for a in range(m + 1):
        column = np.floor(points[:, 0] * 2**a).astype(int)
        row = np.floor(points[:, 1] * 2 ** (m - a)).astype(int)
        found.append(len(set(zip(column.tolist(), row.tolist(), strict=True))))
    return found


def test_the_sobol_points_are_van_der_corput_and_the_direction_numbers_of_x_plus_1():
    index = np.arange(8)
    points = sobol_points(index) * 2.0**-32
    assert points[:, 0].tolist() == [0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875]
    assert points[:, 1].tolist() == [0, 0.5, 0.75, 0.25, 0.625, 0.125, 0.375, 0.875]
    # the direction numbers m_i of the second dimension (Joe and Kuo's table, its dimension 2)
    m = [int(sobol_points([2 ** (i - 1)])[0, 1]) >> (32 - i) for i in range(1, 11)]
    assert m == [1, 3, 5, 15, 17, 51, 85, 255, 257, 771]
    assert reverse_bits(np.array([1, 2**31, 0x12345678])).tolist() == [2**31, 1, 0x1E6A2C48]


@pytest.mark.parametrize("m", [2, 4, 6, 8])
def test_a_scrambled_sobol_set_is_a_net_at_every_power_of_two(m):
    rng = np.random.default_rng(m)
    for _ in range(5):
        seeds = np.tile(rng.integers(0, 2**32, 2), (2**m, 1))
        points = sobol_set(np.arange(2**m), seeds)
        assert ((points >= 0) & (points < 1)).all()
        assert _elementary_cells(points, m) == [2**m] * (m + 1)


def test_owen_scrambling_moves_a_point_anywhere_with_equal_chance():
    seeds = np.arange(20000, dtype=np.uint64) * np.uint64(2654435761) % np.uint64(2**32)
    for value in (0, 2**31, 12345):
        moved = owen_scramble(np.full(20000, value), seeds) * 2.0**-32
        assert stats.kstest(moved, "uniform").pvalue > 0.01


def test_sobol_pixel_samples_are_a_net_of_their_own_in_every_pair():
    samples = PixelSamples(Sampling(64, "sobol", 9), 7)
    every = np.stack([samples.of(np.arange(30), k) for k in range(64)], axis=1)  # (30, 64, 7)
    for pixel in range(30):
        for pair in range(3):
            assert _elementary_cells(every[pixel, :, 2 * pair : 2 * pair + 2], 6) == [64] * 7
        assert sorted(np.floor(every[pixel, :, 6] * 64).astype(int)) == list(range(64))
    assert not np.array_equal(every[0], every[1])  # each pixel scrambled its own way


def test_the_sobol_numbers_are_the_same_bytes_on_every_machine_and_version():
    """Known numbers (times 2^32, integers: the sampler's are exactly that): no library's
    release, processor or vector width may change them, where scipy's scrambling could."""
    samples = PixelSamples(Sampling(16, "sobol", 2024), 5)
    got = np.stack([samples.of(np.array([0, 12345]), k) for k in (0, 1, 15)]) * 2.0**32
    assert got.astype(np.int64).tolist() == [
        [[1088985256, 2964804412, 1099055601, 3070563061, 4121425556],
         [3867171161, 2380059322, 3747437350, 3031037012, 3673283422]],
        [[2786415949, 1903155704, 1382378228, 346146686, 326532251],
         [1759918614, 1208787328, 609299868, 4204956811, 4011985535]],
        [[3921908173, 2852226968, 2218378325, 2157910125, 552419293],
         [880090447, 2465874617, 2637662162, 3651660792, 2871661851]],
    ]  # fmt: skip
    with pytest.raises(ValueError, match="power of two"):
        PixelSamples(Sampling(48, "sobol", 0), 2)


def test_a_sobol_render_imports_no_library_beyond_numpy():
    run = subprocess.run(
        [sys.executable, "-c",
         "import sys; from dataclasses import replace\n"
         "from raykit.io.scene_json import load_scene\nfrom raykit.render import render\n"
         "from raykit.sampling import Sampling\n"
         "scene = load_scene('scenes/soft_shadows.json')\n"
         "scene = replace(scene, camera=replace(scene.camera, width=8, height=6),\n"
         "                sampling=Sampling(4, 'sobol', 1))\n"
         "render(scene, engine='numpy')\n"
         "assert 'scipy' not in sys.modules, 'scipy was imported'\n"],
        capture_output=True, text=True, cwd=REPO,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr


# the noise: counter-based, repeatable


def test_a_uniform_number_is_a_function_of_its_counter_alone():
    pixels = np.arange(1000)
    whole = uniforms(7, pixels[:, None], 3, np.arange(6))
    order = np.random.default_rng(0).permutation(1000)
    for chunk in np.array_split(order, 7):  # any chunks, in any order
        assert whole[chunk].tobytes() == uniforms(7, chunk[:, None], 3, np.arange(6)).tobytes()
    assert uniforms(7, 999, 3, 5) == whole[999, 5]
    assert not np.array_equal(whole, uniforms(8, pixels[:, None], 3, np.arange(6)))
    assert not np.array_equal(whole, uniforms(7, pixels[:, None], 4, np.arange(6)))


def test_the_counter_hash_matches_its_definition_in_plain_integers():
    mask = (1 << 64) - 1

    def mix(z):
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & mask
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & mask
        return z ^ (z >> 31)

    h = 0
    for part in (12345, 678, 9, 2):
        h = mix(((h ^ part) + 0x9E3779B97F4A7C15) & mask)
    assert int(counter_hash(12345, 678, 9, 2)) == h
    assert float(uniforms(12345, 678, 9, 2)) == (h >> 11) * 2.0**-53


def test_the_uniform_numbers_are_uniform_in_0_1():
    numbers = uniforms(2024, np.arange(20000)[:, None], np.arange(4)[None, :], 0).ravel()
    assert numbers.min() >= 0 and numbers.max() < 1
    assert stats.kstest(numbers, "uniform").pvalue > 0.01
    counts = np.bincount(np.floor(numbers * 50).astype(int), minlength=50)
    assert stats.chisquare(counts).pvalue > 0.01


@pytest.mark.parametrize("count", [1, 2, 3, 9, 16, 17, 64, 100])
def test_a_shuffle_is_a_permutation_for_every_key(count):
    for key in range(40):
        p = shuffle(np.arange(count), count, np.full(count, key, dtype=np.uint64))
        assert sorted(p.tolist()) == list(range(count))


def test_a_shuffle_sends_a_cell_anywhere_with_equal_chance():
    keys = np.arange(16000, dtype=np.uint64)
    for cell in (0, 7):
        where = shuffle(np.full(16000, cell), 16, keys)
        assert stats.chisquare(np.bincount(where, minlength=16)).pvalue > 0.01


@pytest.mark.parametrize("sampler", ["random", "jittered", "sobol"])
def test_pixel_samples_are_the_same_bytes_whatever_the_batch(sampler):
    samples = PixelSamples(Sampling(16, sampler, 3), 6)
    pixels = np.arange(300)
    for k in (0, 5, 15):
        whole = samples.of(pixels, k)
        parts = [samples.of(pixels[part], k) for part in (slice(200, 300), slice(0, 200))]
        assert whole.tobytes() == np.vstack(parts[::-1]).tobytes()
        assert ((whole >= 0) & (whole < 1)).all()
    other = PixelSamples(Sampling(16, sampler, 4), 6)
    assert not np.array_equal(whole, other.of(pixels, 15))


def test_jittered_pixel_samples_hold_one_sample_per_cell_in_every_pair():
    n, samples = 4, PixelSamples(Sampling(16, "jittered", 9), 6)
    every = np.stack([samples.of(np.arange(50), k) for k in range(16)], axis=1)  # (50, 16, 6)
    cells = np.floor(every * n).astype(int)
    for pixel in range(50):
        for pair in range(3):
            found = {tuple(c) for c in cells[pixel, :, 2 * pair : 2 * pair + 2]}
            assert len(found) == 16
    # the pixel's own pair keeps sample k in cell k; the others are shuffled against it
    k = np.arange(16)
    assert (cells[:, :, 0] == k % n).all() and (cells[:, :, 1] == k // n).all()
    assert not (cells[:, :, 2] == k % n).all()


def test_each_ray_has_its_own_time_in_the_shutter_interval():
    numbers = np.array([[0.0, 0.25, 0.5], [0.75, 0.125, 0.999]])  # (P, S): 2 pixels, 3 rays each
    times = shutter_times(0.5, 1.5, numbers)
    assert times.tolist() == [[0.5, 0.75, 1.0], [1.25, 0.625, 1.499]]
    assert shutter_times(2.0, 2.0, numbers).tolist() == [[2.0] * 3] * 2  # a shutter of no length


def test_new_dimensions_come_after_the_old_ones_which_keep_their_places():
    old = Dimensions(area_lights=2, max_depth=3)
    assert (old.count, old.light(0, 0), old.light(3, 1)) == (4 + 2 * 4 * 2, 4, 4 + 2 * 7)
    both = Dimensions(2, 3, glossy=True, timed=True)
    assert both.light(3, 1) == old.light(3, 1)
    assert [both.gloss(d) for d in range(3)] == [old.count, old.count + 2, old.count + 4]
    assert (both.time, both.count) == (old.count + 6, old.count + 7)
    timed = Dimensions(2, 3, timed=True)  # no glossy mirror: the time right after the lights
    assert (timed.time, timed.count) == (old.count, old.count + 1)


@pytest.mark.parametrize("sampler", ["random", "jittered", "sobol"])
def test_a_dimensions_numbers_for_all_samples_at_once_are_its_column_sample_by_sample(sampler):
    samples = PixelSamples(Sampling(16, sampler, 7), 7)  # 3 pairs, then a single number
    pixels = np.arange(40)
    every = np.stack([samples.of(pixels, k) for k in range(16)], axis=1)  # (40, 16, 7)
    assert samples.stratum(pixels, 6).tobytes() == every[:, :, 6].tobytes()
    assert ((every >= 0) & (every < 1)).all()


def test_the_jittered_time_puts_one_sample_of_a_pixel_in_each_of_its_n_n_strata():
    samples = PixelSamples(Sampling(16, "jittered", 9), 7)
    times = samples.stratum(np.arange(50), 6)  # (50, 16)
    strata = np.floor(times * 16).astype(int)
    assert (np.sort(strata, axis=1) == np.arange(16)).all()
    # shuffled against the pixel's cells: sample k is not in stratum k in every pixel
    assert not (strata == np.arange(16)).all()

"""The noise kernels (raykit.engine.compiled.noise) against raykit.engine.noise: the counter's
hash on many random counters, its uniform numbers, the shuffle, and each sampler's numbers."""

from __future__ import annotations

import numba
import numpy as np

from raykit.engine import noise
from raykit.engine.compiled import jobs
from raykit.engine.compiled import noise as kernels
from raykit.sampling import Sampling

from .harness import exactly, twin_test

COUNTERS = 100_000


def _counters(rng, count=COUNTERS):
    """Random counters (seed, pixel, sample, dimension) over the parts' whole ranges: seeds to
    2^32 - 1 (the format's largest), pixels to 2^40, samples to 2^32 and the two keys' samples
    (2^64 - 1 and - 2), dimensions to 64."""
    seed = rng.integers(0, 2**32, count)
    pixel = rng.integers(0, 2**40, count)
    sample = rng.integers(0, 2**32, count).astype(np.uint64)
    sample[::7] = noise.SHUFFLE_SAMPLE
    sample[1::7] = noise.SCRAMBLE_SAMPLE
    dimension = rng.integers(0, 64, count)
    return seed, pixel, sample, dimension


@numba.njit
def _each(kernel, seed, pixel, sample, dimension, out):
    for i in range(len(out)):
        out[i] = kernel(seed[i], pixel[i], sample[i], dimension[i])
    return out


def _counter_hash(rng):
    parts = _counters(rng)
    got = _each(kernels.counter_hash, *parts, np.empty(COUNTERS, dtype=np.uint64))
    assert got.dtype == np.uint64
    exactly(got, noise.counter_hash(*parts))


def _uniforms(rng):
    parts = _counters(rng)
    got = _each(kernels.uniforms, *parts, np.empty(COUNTERS))
    exactly(got, noise.uniforms(*parts))
    assert 0 <= got.min() and got.max() < 1


@numba.njit
def _mixed(z):
    out = np.empty(len(z), dtype=np.uint64)
    for i in range(len(z)):
        out[i] = kernels.mix64(z[i])
    return out


def _mix64(rng):
    z = rng.integers(0, 2**63, COUNTERS).astype(np.uint64) * np.uint64(2) + np.uint64(1)
    z[:3] = np.uint64(0), np.uint64(1), np.uint64(0xFFFFFFFFFFFFFFFF)
    exactly(_mixed(z), noise.mix64(z))


@numba.njit
def _shuffled(index, count, key):
    out = np.empty(len(index), dtype=np.int64)
    for i in range(len(index)):
        out[i] = kernels.shuffle(index[i], count, key[i])
    return out


@numba.njit
def _shuffled_by(index, count, key):
    """shuffle_by of each index, its rounds' keys from round_keys."""
    out = np.empty(len(index), dtype=np.int64)
    for i in range(len(index)):
        k0, k1, k2, k3 = kernels.round_keys(key[i])
        out[i] = kernels.shuffle_by(index[i], count, k0, k1, k2, k3)
    return out


@numba.njit
def _shuffled_of_power(index, count, key):
    """shuffle_of_power of each index, its mask and shift made once, as sobol_numbers makes
    them."""
    _, down = kernels.shuffle_shape(count)
    mask = np.uint64(count - 1)
    out = np.empty(len(index), dtype=np.int64)
    for i in range(len(index)):
        k0, k1, k2, k3 = kernels.round_keys(key[i])
        out[i] = kernels.shuffle_of_power(index[i], mask, down, k0, k1, k2, k3)
    return out


def _shuffle(rng):
    """The shuffle, and it again from its rounds' keys made before (round_keys, shuffle_by, and
    in it shuffle_shape and shuffle_rounds)."""
    for count in (1, 2, 3, 4, 9, 16, 17, 64, 100, 256):
        index = rng.integers(0, count, 20_000)
        key = noise.counter_hash(rng.integers(0, 2**32), rng.integers(0, 2**40, 20_000), 0, 1)
        expected = noise.shuffle(index, count, key)
        exactly(_shuffled(index, count, key), expected)
        exactly(_shuffled_by(index, count, key), expected)


def _shuffle_of_power(rng):
    """The shuffle of a power-of-two count in one pass, every index of each count."""
    for count in (1, 2, 4, 8, 64, 1024, 4096):
        index = np.tile(np.arange(count), max(1, 20_000 // count))
        key = noise.counter_hash(rng.integers(0, 2**32), rng.integers(0, 2**40, len(index)), 0, 1)
        expected = noise.shuffle(index, count, key)
        exactly(_shuffled_of_power(index, count, key), expected)


# what the keys' room holds before pixel_keys writes into it: keys it leaves out (a shuffle's
# for one sample a pixel) must not matter
GARBAGE = np.uint64(0x9E3779B97F4A7C15)


@numba.njit
def _batch(seed, pixels, k_first, samples, table, wanted):
    room = jobs.new_sample_room(len(pixels) * samples, len(wanted), len(pixels))
    room.numbers[:] = np.nan
    room.columns[:] = np.nan
    room.keys[:] = GARBAGE
    for q in range(len(pixels)):
        kernels.pixel_keys(kernels.SOBOL, seed, pixels[q], table.shape[1], wanted, room.keys[q])
    kernels.sobol_numbers(k_first, samples, len(pixels), table, wanted, room)
    return room.numbers, room.columns


def _sobol_batch(rng):
    """The Sobol' sampler's numbers of a batch: samples k_first .. k_first + samples - 1 of
    each of its pixels, row q·samples + j and its column the reference's sample k_first + j of
    pixel q, every dimension wanted or some, the others not written."""
    for count, k_first, samples in ((1, 0, 1), (4, 0, 4), (64, 0, 64), (512, 256, 256)):
        for dimensions in (2, 4, 10, 11):
            seed = int(rng.integers(0, 2**32))
            reference = noise.PixelSamples(Sampling(count, "sobol", seed), dimensions)
            pixels = rng.integers(0, 2**24, max(1, 256 // samples))
            table = kernels.sobol_table(count)
            for wanted in (np.ones(dimensions, dtype=np.bool_), _some(dimensions)):
                numbers, columns = _batch(seed, pixels, k_first, samples, table, wanted)
                assert np.isnan(numbers[:, ~wanted]).all() and np.isnan(columns[~wanted]).all()
                for j in range(samples):
                    expected = reference.of(pixels, k_first + j)[:, wanted]
                    exactly(numbers[j::samples][:, wanted], expected)
                    exactly(columns[wanted][:, j::samples].T, expected)


def _some(dimensions):
    """Some of a sample's dimensions wanted, as wanted_dimensions leaves out what a scene does not
    read: a pinhole's lens, a light's point at a mirror depth past 0, (11) the time."""
    some = np.ones(dimensions, dtype=np.bool_)
    some[2 : min(4, dimensions)] = False
    some[6:8] = False
    some[dimensions - 1 :] = dimensions % 2 == 0
    return some


@numba.njit
def _samples(sampler, seed, pixels, k, n, table, wanted):
    out = np.full((len(pixels), len(wanted)), np.nan)
    keys = np.full((len(wanted) // 2 + 2, 6), GARBAGE, dtype=np.uint64)
    reads = np.flatnonzero(wanted)
    count = table.shape[1] if sampler == kernels.SOBOL else n * n
    for i in range(len(pixels)):
        kernels.pixel_keys(sampler, seed, pixels[i], count, wanted, keys)
        kernels.sample_numbers(sampler, k, n, table, wanted, reads, keys, out[i])
    return out


def _pixel_sample(rng):
    """Every sampler's numbers, all dimensions wanted, then some of them only (pairs and the
    last single number left out, as :func:`~raykit.engine.compiled.noise.wanted_dimensions`
    leaves what a scene does not read): the wanted ones the reference's, the others not
    written."""
    for name, count in (("random", 5), ("jittered", 16), ("jittered", 9), ("jittered", 1),
                        ("sobol", 8), ("sobol", 64), ("sobol", 1)):  # fmt: skip
        for dimensions in (2, 4, 10, 11):  # 11: a last single number (a time), in strata
            seed = int(rng.integers(0, 2**32))
            samples = noise.PixelSamples(Sampling(count, name, seed), dimensions)
            sampler = {"random": kernels.RANDOM, "jittered": kernels.JITTERED,
                       "sobol": kernels.SOBOL}[name]  # fmt: skip
            pixels = rng.integers(0, 2**24, 2000)
            every = np.ones(dimensions, dtype=np.bool_)
            some = _some(dimensions)
            table = kernels.sobol_table(count if name == "sobol" else 0)
            for k in range(count):
                expected = samples.of(pixels, k)
                exactly(_samples(sampler, seed, pixels, k, samples.n, table, every), expected)
                got = _samples(sampler, seed, pixels, k, samples.n, table, some)
                exactly(got[:, some], expected[:, some])
                assert np.isnan(got[:, ~some]).all()


@numba.njit
def _in_parts(seed, pixel, sample, dimension):
    out = np.empty((2, len(seed)), dtype=np.uint64)
    uniform = np.empty(len(seed))
    for i in range(len(seed)):
        h = kernels.pixel_hash(seed[i], pixel[i])
        out[0, i] = h
        out[1, i] = kernels.hash_on(h, sample[i], dimension[i])
        uniform[i] = kernels.uniform(out[1, i])
    return out, uniform


def _hash_in_parts(rng):
    """The pixel's hash and the rest folded in: the counter's hash, and its uniform number."""
    seed, pixel, sample, dimension = _counters(rng)
    (start, whole), uniform = _in_parts(seed, pixel, sample, dimension)
    exactly(whole, noise.counter_hash(seed, pixel, sample, dimension))
    exactly(uniform, noise.uniforms(seed, pixel, sample, dimension))
    with np.errstate(over="ignore"):  # the reference's chain, stopped after (seed, pixel)
        h = noise.mix64((np.uint64(0) ^ seed.astype(np.uint64)) + noise.GAMMA)
        h = noise.mix64((h ^ pixel.astype(np.uint64)) + noise.GAMMA)
    exactly(start, h)


def test_the_samplers_constants_are_the_references_order():
    from raykit.sampling import SAMPLERS

    assert [SAMPLERS[i] for i in (kernels.RANDOM, kernels.JITTERED, kernels.SOBOL)] == list(
        SAMPLERS
    )


CHECKS = {
    "noise.mix64": _mix64,
    "noise.counter_hash": _counter_hash,
    "noise.uniforms": _uniforms,
    "noise.shuffle": _shuffle,
    "noise.pixel_hash": _hash_in_parts,
    "noise.hash_on": _hash_in_parts,
    "noise.fold": _hash_in_parts,
    "noise.uniform": _hash_in_parts,
    "noise.round_keys": _shuffle,
    "noise.shuffle_by": _shuffle,
    "noise.shuffle_shape": _shuffle,
    "noise.shuffle_rounds": _shuffle,
    "noise.pixel_keys": _pixel_sample,
    "noise.sample_numbers": _pixel_sample,
    "noise.shuffle_of_power": _shuffle_of_power,
    "noise.sobol_numbers": _sobol_batch,
}
test_the_twin_repeats_its_reference = twin_test("noise", CHECKS)

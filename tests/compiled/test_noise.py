"""The noise kernels (raykit.engine.compiled.noise) against raykit.engine.noise: the counter's
hash on many random counters, its uniform numbers, the shuffle, and each sampler's numbers."""

from __future__ import annotations

import numpy as np
import pytest

from raykit.engine import noise
from raykit.sampling import Sampling

from .harness import exactly, twin_test

numba = pytest.importorskip("numba")
compiled = pytest.importorskip("raykit.engine.compiled")

from raykit.engine.compiled import noise as kernels  # noqa: E402

COUNTERS = 100_000


def _counters(rng, count=COUNTERS):
    """Random counters (seed, pixel, sample, dimension) over the parts' whole ranges: seeds to
    2^32 - 1 (the format's largest), pixels to 2^40, samples to 2^32 and the two keys' samples
    (2^64 - 1 and - 2), dimensions to 64."""
    seed = rng.integers(0, 2**32, count)
    pixel = rng.integers(0, 2**40, count)
    sample = rng.integers(0, 2**32, count).astype(np.uint64)
    sample[::7] = noise.SHUFFLE_SAMPLE
    sample[1::7] = noise.SHIFT_SAMPLE
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


def _shuffle(rng):
    for count in (1, 2, 3, 4, 9, 16, 17, 64, 100, 256):
        index = rng.integers(0, count, 20_000)
        key = noise.counter_hash(rng.integers(0, 2**32), rng.integers(0, 2**40, 20_000), 0, 1)
        exactly(_shuffled(index, count, key), noise.shuffle(index, count, key))


@numba.njit
def _samples(sampler, seed, pixels, k, n, table, dimensions):
    out = np.empty((len(pixels), dimensions))
    for i in range(len(pixels)):
        kernels.pixel_sample(sampler, seed, pixels[i], k, n, table, out[i])
    return out


def _pixel_sample(rng):
    for name, count in (("random", 5), ("jittered", 16), ("jittered", 9), ("sobol", 8)):
        for dimensions in (2, 4, 10, 11):  # 11: a last single number (a time), in strata
            seed = int(rng.integers(0, 2**32))
            samples = noise.PixelSamples(Sampling(count, name, seed), dimensions)
            table = samples.table if samples.table is not None else np.zeros((0, dimensions))
            sampler = {"random": kernels.RANDOM, "jittered": kernels.JITTERED,
                       "sobol": kernels.SOBOL}[name]  # fmt: skip
            pixels = rng.integers(0, 2**24, 2000)
            for k in range(count):
                got = _samples(sampler, seed, pixels, k, samples.n, table, dimensions)
                exactly(got, samples.of(pixels, k))


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
    "noise.pixel_sample": _pixel_sample,
}
test_the_twin_repeats_its_reference = twin_test("noise", CHECKS)

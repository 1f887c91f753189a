"""Repeats :mod:`raykit.engine.noise` for one number at a time: the counter's hash, its uniform
number, the jittered sampler's shuffle, and sample k of a pixel from each sampler.

Every integer here is uint64 and every constant is made one (``np.uint64(...)``): numba, like
numpy, wraps uint64 arithmetic, but it turns uint64 mixed with a signed integer into float64,
which would round the hash. The Sobol' points are not computed here: scipy's, made in Python
(:func:`raykit.sampling.sobol_set`), come in as a table."""

from __future__ import annotations

import numpy as np
from numba import njit

from raykit.engine.compiled.compiling import ONE_RAY
from raykit.engine.compiled.sampling import jittered_point
from raykit.engine.noise import (
    GAMMA,
    MIX1,
    MIX2,
    SHIFT_SAMPLE,
    SHUFFLE_SAMPLE,
    STRATUM_SAMPLE,
    UNIT,
)

# the samplers' numbers, as the kernels take them (raykit.sampling.SAMPLERS' order)
RANDOM, JITTERED, SOBOL = 0, 1, 2


@njit(**ONE_RAY)
def mix64(z):
    """Repeats :func:`raykit.engine.noise.mix64` for one uint64."""
    z = np.uint64(z)
    z = (z ^ (z >> np.uint64(30))) * MIX1
    z = (z ^ (z >> np.uint64(27))) * MIX2
    return z ^ (z >> np.uint64(31))


@njit(**ONE_RAY)
def counter_hash(seed, pixel, sample, dimension):
    """Repeats :func:`raykit.engine.noise.counter_hash` for one counter (each part a
    non-negative integer): its uint64 hash."""
    h = np.uint64(0)
    h = mix64((h ^ np.uint64(seed)) + GAMMA)
    h = mix64((h ^ np.uint64(pixel)) + GAMMA)
    h = mix64((h ^ np.uint64(sample)) + GAMMA)
    return mix64((h ^ np.uint64(dimension)) + GAMMA)


@njit(**ONE_RAY)
def uniforms(seed, pixel, sample, dimension):
    """Repeats :func:`raykit.engine.noise.uniforms` for one counter: the top 53 bits of its
    hash, times 2^-53, in [0, 1)."""
    return np.float64(counter_hash(seed, pixel, sample, dimension) >> np.uint64(11)) * UNIT


@njit(**ONE_RAY)
def shuffle(index, count, key):
    """Repeats :func:`raykit.engine.noise.shuffle` for one ``index`` in [0, count) and its
    ``key`` (uint64): π(index), as an int."""
    bits = 1
    while (1 << bits) < count:  # (count - 1).bit_length(), at least 1
        bits += 1
    mask = np.uint64((1 << bits) - 1)
    down = np.uint64(max(1, bits // 2))
    key = np.uint64(key)
    k0 = mix64(key + np.uint64(1) * GAMMA)
    k1 = mix64(key + np.uint64(2) * GAMMA)
    k2 = mix64(key + np.uint64(3) * GAMMA)
    k3 = mix64(key + np.uint64(4) * GAMMA)
    value = np.uint64(index)
    limit = np.uint64(count)
    one = np.uint64(1)
    while True:
        for k in (k0, k1, k2, k3):
            value = value ^ (k & mask)
            value = (value * ((k >> np.uint64(32)) | one)) & mask  # odd: a bijection
            value = value ^ (value >> down)
            value = value ^ ((value << one) & mask)
        if value < limit:
            return np.int64(value)


@njit(**ONE_RAY)
def pixel_sample(sampler, seed, pixel, k, n, table, out):
    """Repeats :meth:`raykit.engine.noise.PixelSamples.of` for one pixel (r·width + c) and its
    sample k: the sample's uniform numbers into ``out (D,)``, by the ``sampler`` (:data:`RANDOM`,
    :data:`JITTERED` with n x n samples, or :data:`SOBOL` with its points ``table (spp, D)``;
    an empty table for the others)."""
    dimensions = len(out)
    if sampler == SOBOL:  # the image's point k, shifted modulo 1 by the pixel's own numbers
        for d in range(dimensions):
            shifted = table[k, d] + uniforms(seed, pixel, SHIFT_SAMPLE, d)
            out[d] = shifted - 1.0 if shifted >= 1.0 else shifted
        return
    for d in range(dimensions):
        out[d] = uniforms(seed, pixel, k, d)
    if sampler != JITTERED:
        return
    for pair in range(dimensions // 2):  # the pixel's own pair keeps cell k; the others are
        cell = k  # shuffled against it
        if pair:
            cell = shuffle(k, n * n, counter_hash(seed, pixel, SHUFFLE_SAMPLE, pair))
        out[2 * pair], out[2 * pair + 1] = jittered_point(cell, n, out[2 * pair], out[2 * pair + 1])
    if dimensions % 2:  # a last single number (a time): sample k in stratum π(k) of the n·n
        last = dimensions - 1
        stratum = shuffle(k, n * n, counter_hash(seed, pixel, STRATUM_SAMPLE, last))
        out[last] = (stratum + out[last]) / (n * n)

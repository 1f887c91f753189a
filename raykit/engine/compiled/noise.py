"""Repeats :mod:`raykit.engine.noise` for one number at a time: the counter's hash, its uniform
number, the jittered sampler's shuffle, and sample k of a pixel from each sampler.

A pixel's samples share what depends on the pixel alone: its counters' hash as far as (seed, pixel),
its shuffles' round keys and its Sobol' scrambling seeds. :func:`pixel_keys` makes those once per
pixel, and :func:`sample_numbers` each sample's numbers from them, and only the numbers the scene
reads (a pinhole camera reads no point on the lens, a scene without mirrors no light's point past
the first surface): the same operations on the same integers as the reference's, fewer of them per
sample. A scene's sampling reaches the kernels as one :class:`Noise` (:func:`scene_noise`).

Every hash here is uint64 and every constant is made one (``np.uint64(...)``): numba, like
numpy, wraps uint64 arithmetic, but it turns uint64 mixed with a signed integer into float64,
which would round the hash. The shuffles' rounds and the Sobol' points are below 2^32, and kept
in uint32, as :mod:`raykit.engine.compiled.sampling` says why."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from raykit.engine.compiled.camera import lens_tuple
from raykit.engine.compiled.compiling import INLINED, ONE_RAY
from raykit.engine.compiled.sampling import jittered_point, owen_hash, reverse_bits, unit_number
from raykit.engine.noise import (
    GAMMA,
    MIX1,
    MIX2,
    SCRAMBLE_SAMPLE,
    SHUFFLE_SAMPLE,
    STRATUM_SAMPLE,
    UNIT,
    Dimensions,
    PixelSamples,
)
from raykit.sampling import reverse_bits as mirrored
from raykit.sampling import sobol_points
from raykit.scene import Scene

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
def pixel_hash(seed, pixel):
    """Repeats :func:`raykit.engine.noise.counter_hash` as far as its first two parts: the hash
    of (seed, pixel), which every counter of the pixel starts from (:func:`hash_on`)."""
    h = mix64((np.uint64(0) ^ np.uint64(seed)) + GAMMA)
    return mix64((h ^ np.uint64(pixel)) + GAMMA)


@njit(**ONE_RAY)
def hash_on(h, sample, dimension):
    """Repeats the rest of :func:`raykit.engine.noise.counter_hash`: the counter's hash from its
    pixel's, ``h`` (:func:`pixel_hash`), its sample and its dimension folded in."""
    return fold(fold(h, sample), dimension)


@njit(**ONE_RAY)
def fold(h, part):
    """Repeats one step of :func:`raykit.engine.noise.counter_hash`: ``part`` folded into the
    hash ``h`` so far, mix64((h ^ part) + GAMMA). A sample's dimensions share their hash as far
    as (seed, pixel, sample), folded once for all of them (:func:`sample_numbers`)."""
    return mix64((np.uint64(h) ^ np.uint64(part)) + GAMMA)


@njit(**ONE_RAY)
def counter_hash(seed, pixel, sample, dimension):
    """Repeats :func:`raykit.engine.noise.counter_hash` for one counter (each part a
    non-negative integer): its uint64 hash."""
    return hash_on(pixel_hash(seed, pixel), sample, dimension)


@njit(**ONE_RAY)
def uniform(h):
    """Repeats :func:`raykit.engine.noise.uniforms` from a counter's hash ``h``: its top 53
    bits, times 2^-53, in [0, 1)."""
    # below 2^53: the same number as a signed integer, whose conversion is one instruction
    return np.float64(np.int64(np.uint64(h) >> np.uint64(11))) * UNIT


@njit(**ONE_RAY)
def uniforms(seed, pixel, sample, dimension):
    """Repeats :func:`raykit.engine.noise.uniforms` for one counter: the top 53 bits of its
    hash, times 2^-53, in [0, 1)."""
    return uniform(counter_hash(seed, pixel, sample, dimension))


@njit(**ONE_RAY)
def round_keys(key):
    """Repeats the keys of :func:`raykit.engine.noise.shuffle`'s four rounds, from its ``key``
    (uint64): a tuple of four uint64."""
    key = np.uint64(key)
    return (mix64(key + np.uint64(1) * GAMMA), mix64(key + np.uint64(2) * GAMMA),
            mix64(key + np.uint64(3) * GAMMA), mix64(key + np.uint64(4) * GAMMA))  # fmt: skip


@njit(**ONE_RAY)
def shuffle(index, count, key):
    """Repeats :func:`raykit.engine.noise.shuffle` for one ``index`` in [0, count) and its
    ``key`` (uint64): π(index), as an int."""
    k0, k1, k2, k3 = round_keys(key)
    return shuffle_by(index, count, k0, k1, k2, k3)


@njit(**ONE_RAY)
def shuffle_by(index, count, k0, k1, k2, k3):
    """Repeats :func:`raykit.engine.noise.shuffle` for one ``index`` in [0, count), its rounds'
    keys made beforehand (:func:`round_keys`): π(index), as an int. Its rounds walk the value
    back into [0, count) from the next power of two (:func:`shuffle_shape`)."""
    mask, down = shuffle_shape(count)
    value = np.uint32(index)
    limit = np.uint32(count)
    while True:
        value = shuffle_rounds(value, mask, down, k0, k1, k2, k3)
        if value < limit:
            return np.int64(value)


@njit(**INLINED)
def shuffle_shape(count):
    """What :func:`raykit.engine.noise.shuffle`'s rounds take from ``count`` (at most 2^32): the
    ``mask`` of its bits, 2^bits - 1 with bits = (count - 1).bit_length(), at least 1, and the
    shift ``down``, max(1, bits // 2) (uint32 each)."""
    bits = 1
    while (1 << bits) < count:
        bits += 1
    return np.uint32((1 << bits) - 1), np.uint32(max(1, bits // 2))


@njit(**INLINED)
def shuffle_rounds(value, mask, down, k0, k1, k2, k3):
    """The four rounds of :func:`raykit.engine.noise.shuffle` on ``value`` (uint32), within
    ``mask``, by the round keys k0 .. k3 (uint64): each a bijection of [0, mask]. In uint32, as
    :mod:`raykit.engine.compiled.sampling` says why: a key's low 32 bits are all that its mask
    keeps, and of a product, its low 32 bits."""
    one = np.uint32(1)
    for k in (k0, k1, k2, k3):
        low, high = np.uint32(k), np.uint32(k >> np.uint64(32))
        value = np.uint32(value ^ (low & mask))
        value = np.uint32(np.uint32(value * (high | one)) & mask)  # odd: a bijection
        value = np.uint32(value ^ (value >> down))
        value = np.uint32(value ^ (np.uint32(value << one) & mask))
    return value


# INLINED: a call of it per pixel passed its arrays and kept it apart from the loop over a
# batch's pixels, whose hashes the processor could otherwise overlap
@njit(**INLINED)
def pixel_keys(sampler, seed, pixel, count, wanted, keys):
    """What sample k of ``pixel`` (r·width + c) takes from the pixel alone, for
    :func:`sample_numbers`: into ``keys (D // 2 + 2, 6)`` (uint64), at [0, 0] the hash of (seed,
    pixel) (:func:`pixel_hash`); in row 1 + pair, the round keys (:func:`round_keys`) of the
    shuffle of each pair after the first (columns 0 to 3), and for the Sobol' sampler its two
    dimensions' scrambling seeds (columns 4 and 5); in the last row, those of a last single
    number's strata (columns 0 to 3) and its seed (column 4). Only for the dimensions ``wanted
    (D,)`` says the scene reads, and no round keys for a ``count`` of one sample a pixel, whose
    shuffle is π(0) = 0 whatever its keys (its users shuffle nothing then)."""
    dimensions = len(wanted)
    h = pixel_hash(seed, pixel)
    keys[0, 0] = h
    if sampler == RANDOM:
        return
    top = np.uint64(32)
    shuffled = count > 1
    for pair in range(dimensions // 2):
        if wanted[2 * pair] or wanted[2 * pair + 1]:
            row = keys[1 + pair]
            if pair and shuffled:
                row[0], row[1], row[2], row[3] = round_keys(hash_on(h, SHUFFLE_SAMPLE, pair))
            if sampler == SOBOL:
                row[4] = hash_on(h, SCRAMBLE_SAMPLE, 2 * pair) >> top
                row[5] = hash_on(h, SCRAMBLE_SAMPLE, 2 * pair + 1) >> top
    if dimensions % 2 and wanted[dimensions - 1]:
        row = keys[len(keys) - 1]
        if shuffled:
            row[0], row[1], row[2], row[3] = round_keys(hash_on(h, STRATUM_SAMPLE, dimensions - 1))
        if sampler == SOBOL:
            row[4] = hash_on(h, SCRAMBLE_SAMPLE, dimensions - 1) >> top


@njit(**INLINED)
def sample_numbers(sampler, k, n, table, wanted, reads, keys, out):
    """Repeats :meth:`raykit.engine.noise.PixelSamples.of` for one pixel, from its
    :func:`pixel_keys`, and its sample k of ``count`` = n x n (jittered) or ``table.shape[1]``
    (Sobol'): the sample's uniform numbers into ``out (D,)``, by the ``sampler`` (:data:`RANDOM`,
    :data:`JITTERED`, or :data:`SOBOL` with ``table (2, count)``, the Sobol' points of indices 0 ..
    count - 1 with their bits mirrored, :func:`sobol_table`), each dimension ``wanted (D,)``, and
    nothing written to the others (numbers no ray of the scene reads). ``reads``: the dimensions
    wanted, in order (``np.flatnonzero(wanted)``): the loops of one number each go through them
    alone, since a loop over every dimension, made into vector instructions, hashes the unwanted
    ones too and throws them away."""
    h = keys[0, 0]
    dimensions = len(out)
    count = table.shape[1] if sampler == SOBOL else n * n
    if sampler != SOBOL:
        sample_hash = fold(h, k)  # (seed, pixel, sample): what the dimensions' hashes share
        for d in reads:
            out[d] = uniform(fold(sample_hash, d))
        if sampler != JITTERED:
            return
    for pair in range(dimensions // 2):  # the pixel's own pair keeps cell k; the others are
        if not (wanted[2 * pair] or wanted[2 * pair + 1]):  # shuffled against it
            continue
        cell = k
        row = keys[1 + pair]
        if pair and count > 1:  # (a shuffle of one sample is the identity: pixel_keys)
            cell = shuffle_by(k, count, row[0], row[1], row[2], row[3])
        if sampler == SOBOL:  # point π(k) of the pixel's own scrambled net
            if wanted[2 * pair]:
                out[2 * pair] = unit_number(reverse_bits(owen_hash(table[0, cell], row[4])))
            if wanted[2 * pair + 1]:
                out[2 * pair + 1] = unit_number(reverse_bits(owen_hash(table[1, cell], row[5])))
        else:
            out[2 * pair], out[2 * pair + 1] = jittered_point(
                cell, n, out[2 * pair], out[2 * pair + 1]
            )
    if dimensions % 2 and wanted[dimensions - 1]:  # a last single number (a time): sample k in
        last = dimensions - 1  # stratum π(k) of the count
        row = keys[len(keys) - 1]
        stratum = shuffle_by(k, count, row[0], row[1], row[2], row[3]) if count > 1 else 0
        if sampler == SOBOL:  # van der Corput's point π(k), scrambled: π(k) is it mirrored
            out[last] = unit_number(reverse_bits(owen_hash(stratum, row[4])))
        else:
            out[last] = (stratum + out[last]) / count


@njit(**ONE_RAY)
def shuffle_of_power(index, mask, down, k0, k1, k2, k3):
    """:func:`shuffle_by` where the count is a power of two (the Sobol' sampler's every count),
    its ``mask`` count - 1 and ``down`` as :func:`shuffle_shape` makes them, once for a batch: its
    rounds once, with no loop, since they land in [0, count) at once, so that a loop of it over
    many samples becomes vector instructions. For a count of 1, the mask 0 gives π(0) = 0, where
    :func:`shuffle_shape`'s mask of one bit would have to walk back to 0."""
    return np.int64(shuffle_rounds(np.uint32(index), mask, down, k0, k1, k2, k3))


@njit(**INLINED)
def sobol_numbers(k_first, samples, pixels, table, wanted, room):
    """:func:`sample_numbers` of the Sobol' sampler for a batch: samples ``k_first`` to
    ``k_first + samples - 1`` of each of ``pixels`` pixels, from pixel q's :func:`pixel_keys`
    ``room.keys[q]``, into column i = q·samples + j of ``room.columns (D, N)`` and row i of
    ``room.numbers (N, D)`` (a :class:`~.jobs.SampleRoom`), the dimensions ``wanted (D,)`` only:
    the same operations on the same integers, in 32-bit integers, for every sample of the batch
    at once. A pair of dimensions (or a last single number, a time) at a time: each sample's cell
    and its pixel's keys are laid in lanes, ``room.cells (N,)``, ``room.rounds (4, N)`` (the
    shuffle's round keys) and ``room.seeds (2, N)`` (the pair's scrambling seeds), in one pass
    over the batch's pixels; then the cells shuffled, the pair's points read from the table into
    ``room.points (N,)``, and each scrambled into a row of ``columns``, each in a loop of its own
    with no branch, which the compiler turns into vector instructions. (A pixel's few samples
    alone in such a loop stayed one at a time, or too few for its vectors; the table read in it,
    too.) Both dimensions of a pair take the same cells, shuffled once. The rows of ``numbers``
    are copied from ``columns`` after."""
    keys, numbers, columns = room.keys, room.numbers, room.columns
    cells, points, seeds, rounds = room.cells, room.points, room.seeds, room.rounds
    count = table.shape[1]
    _, down = shuffle_shape(count)
    mask = np.uint32(count - 1)  # shuffle_shape's mask for a power of two, but 0 for 1
    dimensions = numbers.shape[1]
    lanes = pixels * samples
    last_row = keys.shape[1] - 1
    for first_dimension in range(0, dimensions, 2):
        single = first_dimension == dimensions - 1  # a last number (a time), its index even
        group = 1 if single else 2
        if not wanted[first_dimension] and (single or not wanted[first_dimension + 1]):
            continue
        row = last_row if single else 1 + first_dimension // 2
        # the pixel's own pair keeps cell k; a shuffle of one sample is the identity (pixel_keys)
        shuffled = (first_dimension >= 2 or single) and count > 1
        for q in range(pixels):
            seed0, seed1 = np.uint32(keys[q, row, 4]), np.uint32(keys[q, row, 5])
            k0, k1, k2, k3 = keys[q, row, 0], keys[q, row, 1], keys[q, row, 2], keys[q, row, 3]
            for i in range(q * samples, (q + 1) * samples):
                cells[i] = k_first + i - q * samples
                seeds[0, i], seeds[1, i] = seed0, seed1
                if shuffled:
                    rounds[0, i], rounds[1, i], rounds[2, i], rounds[3, i] = k0, k1, k2, k3
        if shuffled:
            for i in range(lanes):
                cells[i] = shuffle_of_power(cells[i], mask, down, rounds[0, i], rounds[1, i],
                                            rounds[2, i], rounds[3, i])  # fmt: skip
        for second in range(group):  # the pair's second takes its own seed and row of the table
            d = first_dimension + second
            if not wanted[d]:
                continue
            # a single number is van der Corput's point π(k), π(k) mirrored: the table's first
            # row holds each index mirrored twice, the index itself
            table_row = table[second]
            for i in range(lanes):
                points[i] = table_row[cells[i]]
            out, seed = columns[d], seeds[second]
            for i in range(lanes):
                out[i] = unit_number(reverse_bits(owen_hash(points[i], seed[i])))
            for i in range(lanes):
                numbers[i, d] = out[i]


def sobol_table(count: int) -> np.ndarray:
    """The Sobol' points of indices 0 .. ``count`` - 1, a row per dimension ``(2, count)``
    (uint32), each with its bits mirrored, as :func:`sample_numbers` reads them: made once a
    render by the reference's own :func:`raykit.sampling.sobol_points` and
    :func:`raykit.sampling.reverse_bits`, the same for every pixel (each scrambles its own
    copy)."""
    return np.require(mirrored(sobol_points(np.arange(count))).T, np.uint32, "CAW")


class Noise(NamedTuple):
    """A distributed render's sampling (:mod:`raykit.engine.noise`) as
    :func:`~.render.trace_sampled` takes it: the ``sampler`` (:data:`RANDOM`, ``JITTERED`` or
    ``SOBOL``), the ``seed``, the samples per pixel ``count`` (``n`` x ``n`` for the jittered
    sampler), the Sobol' points ``table (2, count)`` (:func:`sobol_table`; no columns for the other
    samplers), the ``dimensions`` D of a sample, where in them the point in the pixel and on the
    lens lie (``pixel``, ``lens``: :class:`raykit.engine.noise.Dimensions`), and which of them a ray
    of the scene may read, ``wanted (D,)`` (:func:`wanted_dimensions`), and their indices,
    ``reads``."""

    sampler: int
    seed: int
    count: int
    n: int
    table: np.ndarray
    dimensions: int
    pixel: int
    lens: int
    wanted: np.ndarray
    reads: np.ndarray


def wanted_dimensions(scene: Scene, dimensions: Dimensions) -> np.ndarray:
    """Which of a sample's numbers ``(D,)`` a ray of ``scene`` may read: all but the point on
    the lens through a pinhole, and, in a scene without mirrors, where no ray goes past its
    first surface, the area lights' points at a mirror depth past 0 and the glossy bounces'
    numbers. The reference makes them all; each is a hash of its own counter, so the numbers
    read are the same either way."""
    wanted = np.ones(dimensions.count, dtype=np.bool_)
    if not lens_tuple(scene)[0] > 0:  # thin_lens_rays only where the aperture is open
        wanted[Dimensions.lens : Dimensions.lens + 2] = False
    if not scene.materials.mirror.any():  # Shading.is_mirror, without making the rest of it
        deeper = dimensions.light(1, 0)  # from the first light's point at depth 1 to the time
        wanted[deeper : dimensions.time] = False
    return wanted


def scene_noise(scene: Scene) -> Noise:
    """The scene's :class:`Noise`, checked by the reference's own
    :class:`raykit.engine.noise.PixelSamples` (which refuses a jittered count that is not n x n,
    and a Sobol' count that is not a power of two, before any work)."""
    sampling = scene.sampling
    dimensions = Dimensions.of(scene)
    samples = PixelSamples(sampling, dimensions.count)
    sampler = {"random": RANDOM, "jittered": JITTERED, "sobol": SOBOL}[sampling.sampler]
    wanted = wanted_dimensions(scene, dimensions)
    count = sampling.samples_per_pixel
    table = sobol_table(count if sampler == SOBOL else 0)
    return Noise(sampler, sampling.seed, count, samples.n, table, dimensions.count,
                 Dimensions.pixel, Dimensions.lens, wanted, np.flatnonzero(wanted))  # fmt: skip

"""Reproducible noise: the uniform numbers of a distributed render, from a seed and a counter.

A render's random choices (:mod:`raykit.sampling`) must give the same bytes on any machine, at
any tile size, chunk order or thread count, and with either engine. So no number comes from a
stream that is read in order: each is a hash of its *counter* (seed, pixel, sample, dimension),

    ξ = (splitmix64-chain(seed, pixel, sample, dimension) >> 11) · 2^-53   in [0, 1),

computed in uint64 arithmetic that wraps (numpy's, and numba's alike), with 53 bits, every
double in [0, 1) a multiple of 2^-53 reachable. Whichever pixel is rendered first, and in
whatever batch, it gets the same numbers. The chain is splitmix64's finaliser (Steele, Lea and
Flood 2014) applied after each part of the counter is folded in: a bijection of 64 bits, so two
counters that differ only in their last part never collide.

Pixel p = r·width + c. The dimensions of one sample (:class:`Dimensions`): the point in the
pixel, then the point on the lens, then one point per (mirror depth, area light), each a pair;
then, in a scene with a glossy mirror, one pair per mirror bounce (the perturbation of the
reflection at depth 0 .. max_depth - 1); then, in a scene whose shutter is open for a while and
in which a sphere moves, one number (not a pair): the ray's time. Each is appended after the
others only when the scene uses it, so a scene without it keeps its numbers, and its bytes
(the Sobol' set's scrambling depends on how many dimensions it has).

The three samplers (:data:`raykit.sampling.SAMPLERS`) make sample k of a pixel from them:

* ``random``: the numbers themselves;
* ``jittered`` (n x n = samples_per_pixel): pair 0 (the pixel) puts sample k in cell k; every
  other pair in cell π(k), a permutation of the n x n cells drawn per pixel and pair
  (:func:`shuffle`), as FOCG 13.4.2 shuffles the light's samples against the pixel's: without
  it the top left of the pixel would always see the light's top left corner, and the penumbra
  would show the pattern; the time, a single number, is stratified in one dimension: sample k
  takes stratum π(k) of the n·n strata of [0, 1), (π(k) + ξ)/(n·n), π again a permutation
  drawn per pixel (:meth:`PixelSamples.stratum`). So a pixel's n·n rays see n·n different
  slices of the shutter interval, exactly one in each, as its pixel points are one per cell;
* ``sobol``: as ``jittered``, each pair of dimensions from cell k (the pixel's pair) or π(k) (the
  others), but the cell is point k or π(k) of the two-dimensional Sobol' sequence's first
  samples_per_pixel points, a net, scrambled for each pixel and dimension by a seed of its own
  (the top 32 bits of the counter (seed, pixel, SCRAMBLE_SAMPLE, dimension)'s hash:
  :func:`raykit.sampling.sobol_set`); the time takes point π(k) of the first dimension, van der
  Corput's, scrambled the same way. So each pixel's points are a scrambled net of their own,
  and neighbouring pixels' errors do not line up; no number depends on any other library.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from raykit.sampling import (
    SOBOL_BITS,
    Sampling,
    jittered_point,
    owen_scramble,
    sobol_points,
    sobol_set,
)
from raykit.scene import Scene

GAMMA = np.uint64(0x9E3779B97F4A7C15)  # splitmix64's increment: 2^64 / the golden ratio
MIX1 = np.uint64(0xBF58476D1CE4E5B9)
MIX2 = np.uint64(0x94D049BB133111EB)
UNIT = 2.0**-53
# samples no pixel ever takes (counters of sample k are k < 2^32): the keys of a pixel's shuffles
# and of its Sobol' scrambles
SHUFFLE_SAMPLE = np.uint64(0xFFFFFFFFFFFFFFFF)
SCRAMBLE_SAMPLE = np.uint64(0xFFFFFFFFFFFFFFFE)
STRATUM_SAMPLE = np.uint64(0xFFFFFFFFFFFFFFFD)  # the key of a 1-D dimension's shuffle


def mix64(z: np.ndarray) -> np.ndarray:
    """splitmix64's finaliser of ``z`` (uint64, any shape): a bijection of 64-bit integers."""
    z = np.asarray(z, dtype=np.uint64)
    with np.errstate(over="ignore"):
        z = (z ^ (z >> np.uint64(30))) * MIX1
        z = (z ^ (z >> np.uint64(27))) * MIX2
    return z ^ (z >> np.uint64(31))


def counter_hash(seed, pixel, sample, dimension) -> np.ndarray:
    """The 64-bit hash (uint64, the parts' broadcast shape) of the counter (seed, pixel, sample,
    dimension), each a non-negative integer or array of them."""
    h = np.zeros((), dtype=np.uint64)
    with np.errstate(over="ignore"):
        for part in (seed, pixel, sample, dimension):
            h = mix64((h ^ np.asarray(part).astype(np.uint64)) + GAMMA)
    return h


def uniforms(seed, pixel, sample, dimension) -> np.ndarray:
    """Uniform numbers in [0, 1) (float64, the parts' broadcast shape): the top 53 bits of
    :func:`counter_hash`, times 2^-53."""
    return (counter_hash(seed, pixel, sample, dimension) >> np.uint64(11)).astype(np.float64) * UNIT


def shuffle(index: np.ndarray, count: int, key: np.ndarray) -> np.ndarray:
    """π(index) ``(N,)`` for ``index (N,)`` in [0, count): for each ``key (N,)`` (uint64), a
    permutation of [0, count). Four rounds of bijections of the smallest power-of-two range
    holding count (xor a key, multiply by an odd key, xor-shift right and left), repeated while
    the result lies beyond count ("cycle walking"): each step maps the range onto itself, so the
    whole is a permutation of it, and walking keeps those below count a permutation of them."""
    bits = max(1, (count - 1).bit_length())
    mask = np.uint64((1 << bits) - 1)
    down = np.uint64(max(1, bits // 2))
    key = np.asarray(key, dtype=np.uint64)
    with np.errstate(over="ignore"):
        keys = [mix64(key + np.uint64(r + 1) * GAMMA) for r in range(4)]
    value = np.asarray(index).astype(np.uint64)
    walking = np.ones(value.shape, dtype=bool)
    with np.errstate(over="ignore"):
        while walking.any():
            v = value[walking]
            for round_key in keys:
                k = round_key[walking]
                v = v ^ (k & mask)
                v = (v * ((k >> np.uint64(32)) | np.uint64(1))) & mask  # odd: a bijection
                v = v ^ (v >> down)
                v = v ^ ((v << np.uint64(1)) & mask)  # bit i ^= bit i-1: a bijection
            value[walking] = v
            walking = value >= np.uint64(count)
    return value.astype(np.int64)


@dataclass(frozen=True)
class Dimensions:
    """Where each choice of one sample lies among its uniform numbers: ``pixel`` (0, 1),
    ``lens`` (2, 3), then ``light(depth, a)`` for area light a at mirror depth d, then (with
    ``glossy``) ``gloss(depth)`` for the mirror bounce at depth d < max_depth, then (with
    ``timed``) ``time``, one number."""

    area_lights: int
    max_depth: int
    glossy: bool = False  # a mirror of the scene is glossy (glossiness > 0)
    timed: bool = False  # the scene's rays have times of their own (a shutter, a moving sphere)

    pixel = 0
    lens = 2

    @classmethod
    def of(cls, scene: Scene) -> Dimensions:
        """The dimensions a distributed render of ``scene`` takes for each sample."""
        glossy = scene.materials.any_glossy and scene.max_depth > 0
        return cls(scene.area_lights, scene.max_depth, glossy, scene.blurred)

    def light(self, depth: int, a: int) -> int:
        return 4 + 2 * (depth * self.area_lights + a)

    def gloss(self, depth: int) -> int:
        return self.light(self.max_depth + 1, 0) + 2 * depth

    @property
    def time(self) -> int:
        return self.gloss(self.max_depth if self.glossy else 0)

    @property
    def count(self) -> int:
        return self.time + self.timed


class PixelSamples:
    """The uniform numbers of a render's samples: :meth:`of` gives sample k of many pixels."""

    def __init__(self, sampling: Sampling, dimensions: int) -> None:
        self.sampling = sampling
        self.dimensions = dimensions
        spp = sampling.samples_per_pixel
        self.n = math.isqrt(spp)
        if sampling.sampler == "jittered" and self.n * self.n != spp:
            raise ValueError(f"the jittered sampler takes n x n samples per pixel, got {spp}")
        if sampling.sampler == "sobol" and spp & (spp - 1):
            raise ValueError(f"a Sobol' set is balanced at a power of two points, got {spp}")

    def of(self, pixels: np.ndarray, k: int) -> np.ndarray:
        """Sample k's uniform numbers ``(P, dimensions)`` in pixels ``(P,)`` (r·width + c)."""
        seed, dims = self.sampling.seed, np.arange(self.dimensions)
        pixels = np.asarray(pixels, dtype=np.int64)[:, None]
        sampler = self.sampling.sampler
        if sampler == "random":
            return uniforms(seed, pixels, k, dims)
        jitter = uniforms(seed, pixels, k, dims) if sampler == "jittered" else None
        out = np.empty((len(pixels), self.dimensions))
        spp = self.sampling.samples_per_pixel
        for pair in range(self.dimensions // 2):
            cells = np.full(len(pixels), k, dtype=np.int64)
            if pair:  # the pixel's own pair keeps cell k; the others are shuffled against it
                key = counter_hash(seed, pixels[:, 0], SHUFFLE_SAMPLE, pair)
                cells = shuffle(cells, spp, key)
            two = slice(2 * pair, 2 * pair + 2)
            if sampler == "sobol":  # point π(k) of the pixel's own scrambled net
                out[:, two] = sobol_set(cells, self._scrambles(pixels, dims[two]))
            else:
                out[:, two] = jittered_point(cells, self.n, jitter[:, two])
        if self.dimensions % 2:  # the last dimension is a single number: stratified in 1-D
            last = self.dimensions - 1
            out[:, last] = self._strata(
                pixels[:, 0],
                np.full(len(pixels), k),
                last,
                None if jitter is None else jitter[:, last],
            )
        return out

    def stratum(self, pixels: np.ndarray, dimension: int) -> np.ndarray:
        """The numbers ``(P, S)`` of one dimension for all S samples of pixels ``(P,)``: the
        column ``dimension`` of :meth:`of` for k = 0 .. S - 1, made at once (the rays' times,
        which :func:`raykit.sampling.shutter_times` takes a pixel's samples together)."""
        spp = self.sampling.samples_per_pixel
        pixels = np.asarray(pixels, dtype=np.int64)
        samples = np.arange(spp)
        seed = self.sampling.seed
        if self.sampling.sampler == "random":
            return uniforms(seed, pixels[:, None], samples[None, :], dimension)
        if dimension != self.dimensions - 1 or self.dimensions % 2 == 0:
            raise ValueError(f"dimension {dimension} is one of a pair, not a 1-D stratum")
        jitter = None
        if self.sampling.sampler == "jittered":
            jitter = uniforms(seed, pixels[:, None], samples[None, :], dimension).ravel()
        every = np.repeat(pixels, spp)
        strata = self._strata(every, np.tile(samples, len(pixels)), dimension, jitter)
        return strata.reshape(len(pixels), spp)

    def _scrambles(self, pixels: np.ndarray, dims: np.ndarray) -> np.ndarray:
        """The Sobol' sampler's seeds ``(P, len(dims))`` (32 bits) of pixels ``(P, 1)`` in
        dimensions ``dims``: the top half of the hash of (seed, pixel, SCRAMBLE_SAMPLE,
        dimension), each pixel's net scrambled its own way
        (:func:`raykit.sampling.owen_scramble`)."""
        return counter_hash(self.sampling.seed, pixels, SCRAMBLE_SAMPLE, dims) >> np.uint64(32)

    def _strata(
        self,
        pixels: np.ndarray,
        samples: np.ndarray,
        dimension: int,
        jitter: np.ndarray | None,
    ) -> np.ndarray:
        """Sample k's number ``(N,)`` in stratum π(k) of S for pixels ``(N,)``, samples k
        ``(N,)``, π a permutation per pixel and dimension: (π(k) + ξ)/S by their numbers ξ
        ``jitter (N,)`` (jittered); or (Sobol', ``jitter`` None) point π(k) of van der Corput's
        sequence, the first dimension of the Sobol' points, scrambled by the pixel's own seed:
        one number in each of the S strata, as the jittered sampler puts them."""
        spp = self.sampling.samples_per_pixel
        key = counter_hash(self.sampling.seed, pixels, STRATUM_SAMPLE, dimension)
        strata = shuffle(samples, spp, key)
        if jitter is not None:
            return (strata + jitter) / spp
        seeds = self._scrambles(pixels[:, None], np.array([dimension]))[:, 0]
        scrambled = owen_scramble(sobol_points(strata)[:, 0], seeds)
        return scrambled.astype(np.float64) * 2.0**-SOBOL_BITS

"""The sample-pattern kernels (raykit.engine.compiled.sampling) against raykit.sampling, on
random uniform numbers and the corners of the square (0 and the largest double below 1)."""

from __future__ import annotations

import numba
import numpy as np

from raykit import sampling
from raykit.engine.compiled import sampling as kernels
from raykit.rays import normalize

from .harness import exactly, twin_test

COUNT = 20_000
BELOW_ONE = np.nextafter(1.0, 0.0)


def _uniforms(rng):
    """``(COUNT, 2)`` uniform numbers: random, the square's corners and centre, its diagonals
    (where the concentric map changes quarter) and its middle lines (ξ = 1/2: a or b is 0)."""
    xi = rng.uniform(size=(COUNT, 2))
    edges = np.array([0.0, 0.5, BELOW_ONE, 0.25, 0.75])
    xi[: len(edges) ** 2] = np.stack(np.meshgrid(edges, edges), axis=-1).reshape(-1, 2)
    diagonal = rng.uniform(size=500)
    xi[100:600] = np.column_stack([diagonal, diagonal])
    xi[600:1100] = np.column_stack([diagonal, 1.0 - diagonal])
    xi[1100:1600, 0] = 0.5
    return xi


@numba.njit
def _pairs(kernel, a, b):
    out = np.empty((len(a), 2))
    for i in range(len(a)):
        out[i, 0], out[i, 1] = kernel(a[i], b[i])
    return out


def _point_in_pixel(rng):
    rows, cols = rng.integers(0, 4000, COUNT), rng.integers(0, 4000, COUNT)
    xi = _uniforms(rng)

    @numba.njit
    def run(rows, cols, xi):
        out = np.empty((len(rows), 2))
        for i in range(len(rows)):
            out[i, 0], out[i, 1] = kernels.point_in_pixel(rows[i], cols[i], xi[i, 0], xi[i, 1])
        return out

    x, y = sampling.point_in_pixel(rows, cols, xi)
    exactly(run(rows, cols, xi), np.column_stack([x, y]))


def _jittered_point(rng):
    xi = _uniforms(rng)
    for n in (1, 2, 3, 4, 16):
        cells = rng.integers(0, n * n, COUNT)

        @numba.njit
        def run(cells, n, xi):
            out = np.empty((len(cells), 2))
            for i in range(len(cells)):
                out[i, 0], out[i, 1] = kernels.jittered_point(cells[i], n, xi[i, 0], xi[i, 1])
            return out

        exactly(run(cells, n, xi), sampling.jittered_point(cells, n, xi))


def _point_on_parallelogram(rng):
    xi = _uniforms(rng)
    for scale in (1.0, 1e6):
        c, a, b = rng.normal(size=(3, 3)) * scale

        @numba.njit
        def run(c, a, b, xi):
            out = np.empty((len(xi), 3))
            for i in range(len(xi)):
                out[i, 0], out[i, 1], out[i, 2] = kernels.point_on_parallelogram(
                    c[0], c[1], c[2], a[0], a[1], a[2], b[0], b[1], b[2], xi[i, 0], xi[i, 1]
                )
            return out

        exactly(run(c, a, b, xi), sampling.point_on_parallelogram(c, a, b, xi))


def _point_on_disk(rng):
    xi = _uniforms(rng)
    got = _pairs(kernels.point_on_disk, xi[:, 0], xi[:, 1])
    exactly(got, sampling.point_on_disk(xi))
    assert (np.hypot(got[:, 0], got[:, 1]) <= 1.0).all()


def _cos_sin(rng):
    angle = rng.uniform(-np.pi / 4, np.pi / 4, COUNT)
    angle[:4] = 0.0, -0.0, np.pi / 4, -np.pi / 4
    cos, sin = sampling._cos_sin(angle)

    @numba.njit
    def run(angle):
        out = np.empty((len(angle), 2))
        for i in range(len(angle)):
            out[i, 0], out[i, 1] = kernels.cos_sin(angle[i])
        return out

    exactly(run(angle), np.column_stack([cos, sin]))


def _point_on_lens(rng):
    xi = _uniforms(rng)
    for scale in (1.0, 1e6):
        eye, u, v = rng.normal(size=3) * scale, *rng.normal(size=(2, 3))
        aperture = float(rng.uniform(0.01, 2))

        @numba.njit
        def run(e, u, v, aperture, xi):
            out = np.empty((len(xi), 3))
            for i in range(len(xi)):
                out[i, 0], out[i, 1], out[i, 2] = kernels.point_on_lens(
                    e[0], e[1], e[2], u[0], u[1], u[2], v[0], v[1], v[2], aperture, xi[i, 0],
                    xi[i, 1],
                )  # fmt: skip
            return out

        exactly(run(eye, u, v, aperture, xi), sampling.point_on_lens(eye, u, v, aperture, xi))


@numba.njit
def _bases(r):
    out = np.empty((len(r), 9))
    for i in range(len(r)):
        basis = kernels.basis_around(r[i, 0], r[i, 1], r[i, 2])
        for k in range(9):
            out[i, k] = basis[k]
    return out


def _directions(rng):
    """Random directions, some of them not unit, with ties between the magnitudes of their
    components (where np.argmin takes the first) and zeros."""
    r = rng.normal(size=(COUNT, 3)) * rng.choice([1.0, 3.0], size=(COUNT, 1))
    r[:8] = [(1, 1, 1), (-1, 1, 1), (1, -1, 0.5), (0.5, 1, -0.5), (0, 0, 1), (0, 1, 0),
             (1, 0, 0), (-2, 0, 0)]  # fmt: skip
    return r


def _basis_around(rng):
    r = _directions(rng)
    exactly(_bases(r), np.column_stack(sampling.basis_around(r)))


def _perturbed_direction(rng):
    r, xi = normalize(_directions(rng)), _uniforms(rng)
    for a in (0.0, 0.05, 0.4, 2.0):

        @numba.njit
        def run(r, a, xi):
            out = np.empty((len(r), 3))
            for i in range(len(r)):
                out[i, 0], out[i, 1], out[i, 2] = kernels.perturbed_direction(
                    r[i, 0], r[i, 1], r[i, 2], a, xi[i, 0], xi[i, 1]
                )
            return out

        exactly(run(r, a, xi), sampling.perturbed_direction(r, a, xi))


def _shutter_times(rng):
    xi = _uniforms(rng)  # (COUNT, 2): two pixels' worth of samples each
    for shutter in ((0.0, 1.0), (0.25, 0.75), (0.5, 0.5), tuple(sorted(rng.uniform(0, 1e3, 2)))):

        @numba.njit
        def run(shutter_open, shutter_close, xi):
            out = np.empty_like(xi)
            for i in range(xi.shape[0]):
                for j in range(xi.shape[1]):
                    out[i, j] = kernels.shutter_times(shutter_open, shutter_close, xi[i, j])
            return out

        exactly(run(*shutter, xi), sampling.shutter_times(*shutter, xi))


@numba.njit
def _sobol_kernels(index, seeds):
    out = np.empty((len(index), 6), dtype=np.uint64)
    for i in range(len(index)):
        out[i, 0] = kernels.reverse_bits(index[i])
        out[i, 1], out[i, 2] = kernels.sobol_points(index[i])
        out[i, 3] = kernels.owen_scramble(out[i, 1], seeds[i, 0])
        out[i, 4] = kernels.owen_scramble(out[i, 2], seeds[i, 1])
        # the hash alone, on the first dimension mirrored (the index itself), mirrored back
        out[i, 5] = kernels.reverse_bits(kernels.owen_hash(index[i], seeds[i, 0]))
    return out


def _sobol(rng):
    """Every bit of 32 reversed, the Sobol' points of small and large indices, and their
    scrambles."""
    index = np.concatenate([np.arange(4096), rng.integers(0, 2**32, 20_000),
                            2 ** np.arange(32), [2**32 - 1]]).astype(np.uint64)  # fmt: skip
    seeds = rng.integers(0, 2**32, (len(index), 2)).astype(np.uint64)
    got = _sobol_kernels(index, seeds)
    points = sampling.sobol_points(index)
    exactly(got[:, 0], sampling.reverse_bits(index))
    exactly(got[:, 1:3], points)
    exactly(got[:, 3], sampling.owen_scramble(points[:, 0], seeds[:, 0]))
    exactly(got[:, 4], sampling.owen_scramble(points[:, 1], seeds[:, 1]))
    exactly(got[:, 5], got[:, 3])


@numba.njit
def _unit_numbers(values):
    out = np.empty(len(values))
    for i in range(len(values)):
        out[i] = kernels.unit_number(values[i])
    return out


def _unit_number(rng):
    """A point's integer times 2^-32 as sobol_set makes it, for every top bit and the ends."""
    values = np.concatenate([[0, 1, 2**31 - 1, 2**31, 2**31 + 1, 2**32 - 1], 2 ** np.arange(32),
                             rng.integers(0, 2**32, 20_000)]).astype(np.uint32)  # fmt: skip
    exactly(_unit_numbers(values), values.astype(np.uint64) * 2.0**-32)


CHECKS = {
    "sampling.unit_number": _unit_number,
    "sampling.reverse_bits": _sobol,
    "sampling.sobol_points": _sobol,
    "sampling.owen_scramble": _sobol,
    "sampling.owen_hash": _sobol,
    "sampling.basis_around": _basis_around,
    "sampling.perturbed_direction": _perturbed_direction,
    "sampling.point_in_pixel": _point_in_pixel,
    "sampling.jittered_point": _jittered_point,
    "sampling.point_on_parallelogram": _point_on_parallelogram,
    "sampling.point_on_disk": _point_on_disk,
    "sampling.cos_sin": _cos_sin,
    "sampling.point_on_lens": _point_on_lens,
    "sampling.shutter_times": _shutter_times,
}
test_the_twin_repeats_its_reference = twin_test("sampling", CHECKS)

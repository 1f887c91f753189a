"""Repeats :mod:`raykit.sampling` for one sample: the patterns of distributed ray tracing from
its uniform numbers (ξ1, ξ2), the same float64 operations in the same order, so the same bits;
and the Sobol' points and their scrambling, on the same integers (uint64 throughout: numba turns
uint64 mixed with a signed integer into float64, which would round them).
The cosine and sine of the lens's concentric map are :func:`raykit.sampling._cos_sin`'s series,
never the C library's, which differs from numpy's from one processor to the next."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from raykit.engine.compiled.compiling import INLINED, ONE_RAY
from raykit.sampling import COS_COEFFICIENTS, SIN_COEFFICIENTS


@njit(**ONE_RAY)
def point_in_pixel(row, col, u1, u2):
    """Repeats :func:`raykit.sampling.point_in_pixel` for one sample: (x, y) = (c + ξ1, r + ξ2)
    in pixel (row, col)."""
    return float(col) + u1, float(row) + u2


@njit(**ONE_RAY)
def jittered_point(cell, n, u1, u2):
    """Repeats :func:`raykit.sampling.jittered_point` for one cell of the n x n grid: ((i +
    ξ1)/n, (j + ξ2)/n) for cell = i + n·j. Where n is a power of two (the jittered sampler's
    4^k samples per pixel), with no division, the costliest operation of a sample's numbers: i
    is the cell's low bits, n·j the rest, and a quotient by n is the product by 1/n, both exact
    (a power of two only moves the exponent), so the bits are the same."""
    if n & (n - 1) == 0:
        inverse = 1.0 / n
        i = cell & (n - 1)
        return (float(i) + u1) * inverse, (float(cell - i) * inverse + u2) * inverse
    return (float(cell % n) + u1) / n, (float(cell // n) + u2) / n


@njit(**ONE_RAY)
def point_on_parallelogram(c0, c1, c2, a0, a1, a2, b0, b1, b2, u1, u2):
    """Repeats :func:`raykit.sampling.point_on_parallelogram` for one sample: c + ξ1·a + ξ2·b."""
    return c0 + u1 * a0 + u2 * b0, c1 + u1 * a1 + u2 * b1, c2 + u1 * a2 + u2 * b2


@njit(**INLINED)
def cos_sin(angle):
    """Repeats :func:`raykit.sampling._cos_sin` for one angle in [-π/4, π/4]: its Taylor
    series, Horner's way, in the reference's order, by the same coefficients."""
    x2 = angle * angle
    cos = 1.0
    sin = 1.0
    for k in range(len(COS_COEFFICIENTS) - 1, -1, -1):
        cos = 1.0 - x2 * COS_COEFFICIENTS[k] * cos
        sin = 1.0 - x2 * SIN_COEFFICIENTS[k] * sin
    return cos, angle * sin


@njit(**INLINED)
def point_on_disk(u1, u2):
    """Repeats :func:`raykit.sampling.point_on_disk` for one sample: Shirley and Chiu's
    concentric map of (ξ1, ξ2) to the unit disk."""
    a = 2.0 * u1 - 1.0
    b = 2.0 * u2 - 1.0
    wide = abs(a) > abs(b)
    radius = a if wide else b
    if radius == 0:  # the centre: any angle (the reference's 0/0 is replaced so)
        angle = 0.0
    else:
        angle = (math.pi / 4) * (b / a if wide else a / b)
    cos, sin = cos_sin(angle)
    if wide:
        return radius * cos, radius * sin
    return radius * sin, radius * cos


@njit(**INLINED)
def point_on_lens(e0, e1, e2, u0, u1, u2, v0, v1, v2, aperture, x1, x2):
    """Repeats :func:`raykit.sampling.point_on_lens` for one sample (ξ1, ξ2) = (``x1``, ``x2``):
    e + (aperture/2)·(x·u + y·v), (x, y) the point on the unit disk."""
    x, y = point_on_disk(x1, x2)
    radius = aperture / 2.0
    return (
        e0 + radius * (x * u0 + y * v0),
        e1 + radius * (x * u1 + y * v1),
        e2 + radius * (x * u2 + y * v2),
    )


@njit(**ONE_RAY)
def basis_around(r0, r1, r2):
    """Repeats :func:`raykit.sampling.basis_around` for one direction r: (u, v, w) as nine
    numbers, w = r/|r|, t = w with its smallest component by magnitude (the first of equals) set
    to 1, u = t × w / |t × w|, v = w × u, each cross product as numpy's (a1·b2 - a2·b1, ...)."""
    length = math.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    w0, w1, w2 = r0 / length, r1 / length, r2 / length
    t0, t1, t2 = w0, w1, w2
    if abs(w0) <= abs(w1) and abs(w0) <= abs(w2):  # np.argmin: the first of equals
        t0 = 1.0
    elif abs(w1) <= abs(w2):
        t1 = 1.0
    else:
        t2 = 1.0
    c0, c1, c2 = t1 * w2 - t2 * w1, t2 * w0 - t0 * w2, t0 * w1 - t1 * w0
    length = math.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    u0, u1, u2 = c0 / length, c1 / length, c2 / length
    v0, v1, v2 = w1 * u2 - w2 * u1, w2 * u0 - w0 * u2, w0 * u1 - w1 * u0
    return u0, u1, u2, v0, v1, v2, w0, w1, w2


@njit(**ONE_RAY)
def perturbed_direction(r0, r1, r2, a, x1, x2):
    """Repeats :func:`raykit.sampling.perturbed_direction` for one unit direction r and the
    uniform numbers (ξ1, ξ2) = (``x1``, ``x2``): normalize(r + u'·u + v'·v), u' = -a/2 + ξ1·a,
    v' = -a/2 + ξ2·a, in the basis of :func:`basis_around`."""
    u0, u1, u2, v0, v1, v2, _, _, _ = basis_around(r0, r1, r2)
    along_u = -a / 2 + x1 * a
    along_v = -a / 2 + x2 * a
    p0 = r0 + along_u * u0 + along_v * v0
    p1 = r1 + along_u * u1 + along_v * v1
    p2 = r2 + along_u * u2 + along_v * v2
    length = math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
    return p0 / length, p1 / length, p2 / length


@njit(**ONE_RAY)
def shutter_times(shutter_open, shutter_close, u):
    """Repeats :func:`raykit.sampling.shutter_times` for one ray: its time T = T0 + ξ·(T1 - T0)
    in the shutter interval [T0, T1] from its own number ξ."""
    return shutter_open + u * (shutter_close - shutter_open)


# the Sobol' sampler's integers are below 2^32, and the reference's uint64 operations on them keep
# only their low 32 bits (each product masked): the same operations in uint32 give the same bits,
# and a loop of them makes vector instructions of twice the lanes, with the 32-bit multiply
# that AVX2 has (it has no 64-bit one). numba widens a uint32 sum or product to 64 bits: each
# step is cut back to 32 (np.uint32), which the compiler keeps as 32-bit arithmetic.
_U1, _U2, _U4, _U8, _U16 = (np.uint32(k) for k in (1, 2, 4, 8, 16))
_SWAPS = (
    np.uint32(0x55555555),
    np.uint32(0x33333333),
    np.uint32(0x0F0F0F0F),
    np.uint32(0x00FF00FF),
)
_OWEN = tuple(np.uint32(c) for c in (0x3D20ADEA, 0x05526C56, 0x53A22864))
_TOP_BIT = np.uint32(0x80000000)


@njit(**ONE_RAY)
def reverse_bits(value):
    """Repeats :func:`raykit.sampling.reverse_bits` for one integer below 2^32: its 32 bits in
    reverse order, as uint32."""
    m1, m2, m4, m8 = _SWAPS
    v = np.uint32(value)
    v = np.uint32(((v >> _U1) & m1) | ((v & m1) << _U1))
    v = np.uint32(((v >> _U2) & m2) | ((v & m2) << _U2))
    v = np.uint32(((v >> _U4) & m4) | ((v & m4) << _U4))
    v = np.uint32(((v >> _U8) & m8) | ((v & m8) << _U8))
    return np.uint32((v >> _U16) | (v << _U16))


@njit(**ONE_RAY)
def unit_number(value):
    """A point's 32-bit integer ``value`` (uint32) times 2^-32, in [0, 1), as
    :func:`raykit.sampling.sobol_set` makes it: float(value)·2^-32 exactly, float(value) taken as
    the signed value - 2^31 plus 2^31 (each exact), a conversion AVX2 makes for vectors, where it
    has none from unsigned integers."""
    signed = np.int32(np.uint32(value) ^ _TOP_BIT)  # value - 2^31, as a signed 32-bit integer
    return (np.float64(signed) + 2147483648.0) * 2.0**-32


@njit(**ONE_RAY)
def sobol_points(index):
    """Repeats :func:`raykit.sampling.sobol_points` for one index below 2^32: its point of the
    two-dimensional Sobol' sequence, as two uint64 integers below 2^32."""
    index = np.uint64(index)
    second = np.uint64(0)
    m = np.uint64(1)
    one = np.uint64(1)
    i = np.uint64(1)
    while (index >> (i - one)) != np.uint64(0):  # the direction numbers of the bits set
        if (index >> (i - one)) & one:
            second = second ^ (m << (np.uint64(32) - i))
        m = (m << one) ^ m
        i += one
    return reverse_bits(index), second


@njit(**ONE_RAY)
def owen_scramble(value, seed):
    """Repeats :func:`raykit.sampling.owen_scramble` for one 32-bit value and its 32-bit seed
    (both uint64)."""
    return reverse_bits(owen_hash(reverse_bits(value), seed))


@njit(**ONE_RAY)
def owen_hash(mirrored, seed):
    """The hash of :func:`raykit.sampling.owen_scramble` alone, on a 32-bit value whose bits are
    mirrored already, and its 32-bit seed: the scrambled value, still mirrored, as uint32. (A
    Sobol' point's first dimension is its index mirrored: its scramble needs no mirroring in.)"""
    c1, c2, c3 = _OWEN
    seed = np.uint32(seed)
    v = np.uint32(mirrored)
    v = np.uint32(v ^ np.uint32(v * c1))
    v = np.uint32(v + seed)
    v = np.uint32(v * np.uint32((seed >> _U16) | _U1))
    v = np.uint32(v ^ np.uint32(v * c2))
    return np.uint32(v ^ np.uint32(v * c3))

"""Sampling (FOCG 13.4): the sample patterns of distributed ray tracing, from uniform numbers.

Distributed ray tracing (Cook et al. 1984) sends many rays per pixel, each with its own random
choices: where in the pixel it passes, where on the lens it starts, which point of an area light
its shadow ray aims at, how a glossy reflection is perturbed, at what time in the shutter
interval it sees a moving scene. Each choice is a point of a 2D pattern (or, for the time, a
number) made from uniform numbers, and every function here is a pure function of those numbers.

Conventions (owned here; the renderer's noise, :mod:`raykit.engine.noise`, refers to this page)
-----------------------------------------------------------------------------------------------
* A uniform number ξ lies in [0, 1). Patterns take them as ``uniforms (N, 2)`` (ξ1, ξ2) per
  row, and give one sample per row, in the same order; no function draws a random number
  itself, so that each is tested exactly on given numbers, and the renderer decides where the
  numbers come from (a seed, the pixel, the sample and the dimension: reproducible noise).
* A sample set of a pixel is ``(n, 2)`` points in the unit square [0, 1)²: ``random`` takes the
  numbers as they are (:func:`random_set`); ``jittered`` (stratified, FOCG 13.4.1) puts sample
  k = i + n·j of n x n into cell (i, j), column i, row j, at ((i + ξ1)/n, (j + ξ2)/n)
  (:func:`jittered_set`, a sample at a time :func:`jittered_point`): exactly one sample in
  each cell. The low-discrepancy set is :func:`sobol_set` (below), as integers
  :func:`sobol_points` scrambled by :func:`owen_scramble`.
* A point in a pixel: x = c + ξ1, y = r + ξ2, the continuous image coordinates of
  :mod:`raykit.camera` (row r from the top, so ξ2 runs *down* the pixel).
* An area light is a parallelogram, like a billboard: corner c, edges a and b, its points
  c + ξ1·a + ξ2·b (FOCG 13.4.2), :func:`point_on_parallelogram`.
* The thin lens (FOCG 13.4.3) is a disk of *radius* aperture/2 around the eye, in the camera's
  u, v plane (the aperture is the lens's diameter: taking it for the radius doubles the blur,
  the classic mistake). The unit square goes to the unit disk by Shirley and Chiu's concentric
  map (:func:`point_on_disk`): it keeps area (uniform numbers give uniform points) *and* keeps
  strata compact, each square cell going to a piece of the disk of about the same shape, so a
  jittered set stays jittered on the lens. The polar map (r = √ξ1, θ = 2π·ξ2) keeps area too,
  but stretches the cells into long thin wedges and sectors, and loses most of the gain.
* A perturbed direction (glossy reflection, FOCG 13.4.4): the unit direction r, moved within the
  square of side a perpendicular to r, in the orthonormal basis (u, v, w) with w = r
  (:func:`basis_around`): r' = normalize(r + u'·u + v'·v), u' = -a/2 + ξ1·a, v' = -a/2 + ξ2·a.
  The basis must be orthonormal: with u and v of other lengths, or not perpendicular to r, the
  square is stretched or tilted and the reflection blurs more one way than the other.
* A time in the shutter interval (motion blur, Cook et al. 1984; FOCG 13.4.5): the shutter is
  open from T0 to T1 (the book's capital T, not the ray's t), and each *ray*, each sample of
  each pixel, sees the scene at its own time T = T0 + ξ·(T1 - T0) from its own uniform number
  (:func:`shutter_times`); a sphere moving with velocity v is then at c + T·v
  (:func:`raykit.spheres.center_at`). A time per pixel,
  shared by its samples, shows each pixel the moving object at one instant: the mean over the
  samples no longer blurs it, and the streak is noise (each pixel all object or all background).

Which low-discrepancy sequence, and why made here. The Sobol' sampler takes, for each pair of
dimensions (the point in the pixel, on the lens, on a light...), the first count = 2^m points of
the two-dimensional Sobol' sequence (:func:`sobol_points`): its first dimension is van der
Corput's, the bits of the index mirrored about the binary point, its second the XOR of the
direction numbers of the polynomial x + 1 for the index's set bits. Every power-of-two prefix of
it is a (0, m, 2)-net: each of the 2^m points lies alone in every box of area 2^-m whose sides
are powers of two, 2^m x 1, 2^(m-1) x 2, ..., 1 x 2^m (jittered sampling keeps one point per
cell of the n x n boxes only). Each pixel scrambles its own copy (Owen's nested uniform
scrambling, :func:`owen_scramble`: each bit flipped by a choice that depends on the bits above
it alone, so that the scrambled points are still a net, and each point is uniform), and each
pair of dimensions but the pixel's takes the points in an order of its own (the same shuffle as
the jittered sampler's: Kollig and Keller's padding, 2002), so that the pairs are independent of
one another. Two things that were tried before and lost: one scrambled net for the whole image,
each pixel's copy shifted modulo 1 (a Cranley-Patterson rotation), which is no longer a net and
fell behind jittered sampling past 16 samples a pixel; and scipy's scrambled Sobol' sequence,
whose bytes no scipy release promises to keep (its scrambling draws from numpy's generator, in
an order that is its implementation's), where a render must give the same bytes on any machine
and with any version of its libraries. Integers of 32 bits, in uint64 arithmetic that neither
engine can round; a number is the integer times 2^-32. The price of a net: a Sobol' set is
balanced only at a power of two, so the sampler takes ``samples_per_pixel`` = 2^m (the scene
loader says so).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from raykit.rays import normalize

SAMPLERS = ("random", "jittered", "sobol")


@dataclass(frozen=True)
class Sampling:
    """How a render samples (format v2's ``render``): ``samples_per_pixel``, the ``sampler``
    (one of :data:`SAMPLERS`), the ``seed`` its uniform numbers come from, and the ``shutter``
    interval (T0, T1) its rays' times lie in (None: no shutter, every ray at time 0)."""

    samples_per_pixel: int = 1
    sampler: str = "jittered"
    seed: int = 0
    shutter: tuple[float, float] | None = None  # (T0, T1), 0 <= T0 <= T1; None: every ray at 0


def point_in_pixel(
    rows: np.ndarray, cols: np.ndarray, uniforms: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The image points (x, y) = (c + ξ1, r + ξ2), each ``(N,)``, in pixels (rows, cols)
    ``(N,)`` from ``uniforms (N, 2)``. A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: x = c + ξ1, y = r + ξ2 (column c, row r): each (N,)
    uniforms = np.asarray(uniforms, dtype=float)
    x = np.asarray(cols, dtype=float) + uniforms[:, 0]
    y = np.asarray(rows, dtype=float) + uniforms[:, 1]
    return x, y
    # END SOLUTION


def random_set(uniforms: np.ndarray) -> np.ndarray:
    """The random (uniform) sample set ``(n, 2)`` in the unit square: the numbers
    ``uniforms (n, 2)`` themselves, each sample anywhere, independent of the others.
    A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: the random set is the uniform numbers themselves, as a new (n, 2) float array
    return np.array(uniforms, dtype=float)
    # END SOLUTION


def jittered_point(cells: np.ndarray, n: int, uniforms: np.ndarray) -> np.ndarray:
    """Points ``(N, 2)`` jittered in cells ``(N,)`` of the n x n grid of the unit square (FOCG
    13.4.1): cell k = i + n·j (column i, row j) gives ((i + ξ1)/n, (j + ξ2)/n), from
    ``uniforms (N, 2)``. A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: cell k is column i = k mod n, row j = k div n; its point is ((i + ξ1)/n, (j + ξ2)/n)
    cells = np.asarray(cells)
    grid = np.column_stack([cells % n, cells // n]).astype(float)  # (N, 2): column i, row j
    return (grid + np.asarray(uniforms, dtype=float)) / n
    # END SOLUTION


def jittered_set(n: int, uniforms: np.ndarray) -> np.ndarray:
    """The jittered (stratified) set of n x n samples ``(n*n, 2)`` in the unit square (FOCG
    13.4.1): sample k in cell k (:func:`jittered_point`), so exactly one sample in each cell,
    from ``uniforms (n*n, 2)``. A stage-5 student function."""
    uniforms = np.asarray(uniforms, dtype=float)
    if uniforms.shape != (n * n, 2):
        raise ValueError(f"a jittered set of {n} x {n} takes ({n * n}, 2), got {uniforms.shape}")
    # BEGIN SOLUTION
    # hint: sample k in cell k, k = 0 … n·n - 1: jittered_point of every cell
    return jittered_point(np.arange(n * n), n, uniforms)
    # END SOLUTION


def point_on_parallelogram(
    corner: np.ndarray, edge1: np.ndarray, edge2: np.ndarray, uniforms: np.ndarray
) -> np.ndarray:
    """Points c + ξ1·a + ξ2·b ``(N, 3)`` of the parallelogram with ``corner`` c and edges
    ``edge1`` a and ``edge2`` b ``(3,)`` (FOCG 13.4.2's area light), from ``uniforms (N, 2)``.
    A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: c + ξ1·a + ξ2·b for each row (ξ1, ξ2) of uniforms: shape (N, 3)
    uniforms = np.asarray(uniforms, dtype=float)
    c, a, b = (np.asarray(x, dtype=float) for x in (corner, edge1, edge2))
    return c + uniforms[:, 0:1] * a + uniforms[:, 1:2] * b
    # END SOLUTION


def point_on_disk(uniforms: np.ndarray) -> np.ndarray:
    """Points ``(N, 2)`` of the unit disk from ``uniforms (N, 2)`` in the unit square, by
    Shirley and Chiu's concentric map: (a, b) = 2ξ - 1 in [-1, 1)²; the square ring
    max(|a|, |b|) = ρ goes to the circle of radius ρ, so area is kept and strata stay compact
    (see the module page). A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: (a, b) = 2ξ - 1; where |a| > |b|: radius a, φ = (π/4)·(b/a), else radius b,
    #       φ = π/2 - (π/4)·(a/b); the point radius·(cos φ, sin φ) (radius 0 at the centre);
    #       _cos_sin gives cos and sin of angles in [-π/4, π/4]
    uniforms = np.asarray(uniforms, dtype=float)
    a = 2.0 * uniforms[:, 0] - 1.0
    b = 2.0 * uniforms[:, 1] - 1.0
    wide = np.abs(a) > np.abs(b)  # the left and right quarters of the square
    radius = np.where(wide, a, b)
    # φ = (π/4)·(b/a) in the wide quarters, else φ = π/2 - θ with θ = (π/4)·(a/b), whose cosine
    # and sine are θ's sine and cosine: both angles lie in [-π/4, π/4]
    with np.errstate(invalid="ignore", divide="ignore"):
        angle = (math.pi / 4) * np.where(wide, b / a, a / b)
    angle = np.where(radius == 0, 0.0, angle)  # the centre (a = b = 0): any angle, radius 0
    cos, sin = _cos_sin(angle)
    return np.column_stack([radius * np.where(wide, cos, sin), radius * np.where(wide, sin, cos)])
    # END SOLUTION


# the series' coefficients 1/((2k-1)·2k) (cosine) and 1/(2k·(2k+1)) (sine), k = 1 .. 8: to
# x^16 and x^17, whose next terms are below half an ulp on [-π/4, π/4]; each a product by a
# number made once, where a quotient by (2k-1)·2k waited on the divider for every angle
COS_COEFFICIENTS = tuple(1.0 / ((2 * k - 1) * (2 * k)) for k in range(1, 9))
SIN_COEFFICIENTS = tuple(1.0 / ((2 * k) * (2 * k + 1)) for k in range(1, 9))


def _cos_sin(angle: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """cos and sin of angles ``(N,)`` in [-π/4, π/4] by their Taylor series (to within an ulp
    there), in plain multiplications and additions: numpy's own np.cos and np.sin are
    vectorised differently on different processors, and a render must be the same bytes on
    every machine (and in a numba kernel). Horner's way, from the last term in:
    cos = 1 - x²·c1·(1 - x²·c2·(1 - ...)), c_k = :data:`COS_COEFFICIENTS`, and sin likewise."""
    x2 = angle * angle
    cos = np.ones_like(angle)
    sin = np.ones_like(angle)
    for k in range(len(COS_COEFFICIENTS) - 1, -1, -1):
        cos = 1.0 - x2 * COS_COEFFICIENTS[k] * cos
        sin = 1.0 - x2 * SIN_COEFFICIENTS[k] * sin
    return cos, angle * sin


def point_on_lens(
    eye: np.ndarray, u: np.ndarray, v: np.ndarray, aperture: float, uniforms: np.ndarray
) -> np.ndarray:
    """Points ``(N, 3)`` on the thin lens: the disk of radius aperture/2 (the aperture is the
    lens's diameter) around ``eye (3,)`` in the plane of the camera's ``u`` and ``v`` ``(3,)``,
    e + (aperture/2)·(x·u + y·v) with (x, y) = :func:`point_on_disk` of ``uniforms (N, 2)``.
    A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: (x, y) = point_on_disk(uniforms); e + (aperture/2)·(x·u + y·v): the aperture is the
    #       lens's diameter
    disk = point_on_disk(uniforms)
    radius = aperture / 2.0
    return np.asarray(eye, dtype=float) + radius * (
        disk[:, 0:1] * np.asarray(u, dtype=float) + disk[:, 1:2] * np.asarray(v, dtype=float)
    )
    # END SOLUTION


def basis_around(r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """An orthonormal basis (u, v, w), each ``(N, 3)``, with w = r/|r| for ``r (N, 3)`` (FOCG
    2.4.6): t is w with its smallest component (by magnitude; the first of equals) set to 1,
    u = t × w / |t × w|, v = w × u; right-handed. A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: w = r/|r|; t = w with its smallest component (by magnitude, the first of equals) set
    #       to 1; u = t × w / |t × w|, v = w × u
    w = normalize(r)
    t = w.copy()
    smallest = np.argmin(np.abs(w), axis=1)
    t[np.arange(len(w)), smallest] = 1.0
    u = normalize(np.cross(t, w))
    v = np.cross(w, u)
    return u, v, w
    # END SOLUTION


def perturbed_direction(r: np.ndarray, a: float, uniforms: np.ndarray) -> np.ndarray:
    """Unit directions ``(N, 3)``: unit ``r (N, 3)`` moved within the square of side ``a`` (a
    number, or each row's own, ``(N, 1)``) perpendicular to it (FOCG 13.4.4, glossy
    reflection): r' = normalize(r + u'·u + v'·v) with u' = -a/2 + ξ1·a, v' = -a/2 + ξ2·a in the
    basis of :func:`basis_around`, from ``uniforms (N, 2)``. A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: u, v from basis_around(r); u' = -a/2 + ξ1·a, v' = -a/2 + ξ2·a;
    #       normalize(r + u'·u + v'·v)
    uniforms = np.asarray(uniforms, dtype=float)
    u, v, _ = basis_around(r)
    along_u = -a / 2 + uniforms[:, 0:1] * a
    along_v = -a / 2 + uniforms[:, 1:2] * a
    return normalize(np.asarray(r, dtype=float) + along_u * u + along_v * v)
    # END SOLUTION


def shutter_times(shutter_open: float, shutter_close: float, uniforms: np.ndarray) -> np.ndarray:
    """The times T = T0 + ξ·(T1 - T0) ``(P, S)`` of the S samples (rays) of each of P pixels, in
    the shutter interval [T0, T1] = [``shutter_open``, ``shutter_close``], each from its own
    number ``uniforms (P, S)`` (motion blur; the module page). A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: every ray its own time: T0 + ξ·(T1 - T0) for each sample of each pixel, not one
    #       time per pixel shared by its samples
    return shutter_open + np.asarray(uniforms, dtype=float) * (shutter_close - shutter_open)
    # END SOLUTION


SOBOL_BITS = 32  # the bits of a Sobol' point's integer: the number is it times 2^-32
_MASK = np.uint64(2**SOBOL_BITS - 1)


def reverse_bits(values: np.ndarray) -> np.ndarray:
    """The 32 bits of each of ``values (N,)`` (non-negative integers below 2^32) in reverse
    order, as uint64: bit i becomes bit 31 - i. Swaps of ever larger blocks: neighbouring bits,
    then pairs, nibbles, bytes and halves."""
    v = np.asarray(values).astype(np.uint64)
    for shift, mask in ((1, 0x55555555), (2, 0x33333333), (4, 0x0F0F0F0F), (8, 0x00FF00FF)):
        shift, mask = np.uint64(shift), np.uint64(mask)
        v = ((v >> shift) & mask) | ((v & mask) << shift)
    return ((v >> np.uint64(16)) | (v << np.uint64(16))) & _MASK


def sobol_points(index: np.ndarray) -> np.ndarray:
    """Points ``index (N,)`` (non-negative integers below 2^32) of the two-dimensional Sobol'
    sequence, as integers ``(N, 2)`` (uint64, below 2^32; the point is them times 2^-32).
    Dimension 0 is van der Corput's: the index's bits mirrored (:func:`reverse_bits`).
    Dimension 1 XORs, for each bit i = 1, 2, ... of the index that is set, the direction number
    v_i = m_i·2^(32-i), with m_1 = 1 and m_i = 2·m_(i-1) XOR m_(i-1): the recurrence of the
    primitive polynomial x + 1 (Sobol' 1967; Bratley and Fox 1988). Points 1 to 4 are (0.5,
    0.5), (0.25, 0.75), (0.75, 0.25), (0.125, 0.625): the index's own order, not the Gray code's
    (each power-of-two prefix is the same set either way)."""
    index = np.asarray(index).astype(np.uint64)
    second = np.zeros_like(index)
    m = 1
    for i in range(1, SOBOL_BITS + 1):
        if not (index >> np.uint64(i - 1)).any():  # no higher bit set anywhere
            break
        bit = (index >> np.uint64(i - 1)) & np.uint64(1)
        second = second ^ (bit * np.uint64(m << (SOBOL_BITS - i)))
        m = (m << 1) ^ m
    return np.column_stack([reverse_bits(index), second])


def owen_scramble(values: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """Owen's nested uniform scrambling of 32-bit ``values (N,)``, each by its ``seeds (N,)``
    (32-bit), as a hash (Laine and Karras 2011; these constants Vegdahl's, as Burley 2020 uses
    them): with the bits mirrored (:func:`reverse_bits`), a hash in which each bit depends on the
    bits below it and the seed only (a multiply by an even number, an add and a multiply by an
    odd one carry upward, never down), mirrored back: each bit of the value is flipped or not by
    a choice that depends on the bits above it alone. So a set of 2^m points in 2^m strata (of
    any power-of-two sides) keeps one in each, each moved to a uniform place in its own."""
    seeds = np.asarray(seeds).astype(np.uint64)
    v = reverse_bits(values)
    v = v ^ ((v * np.uint64(0x3D20ADEA)) & _MASK)
    v = (v + seeds) & _MASK
    v = (v * ((seeds >> np.uint64(16)) | np.uint64(1))) & _MASK
    v = v ^ ((v * np.uint64(0x05526C56)) & _MASK)
    v = v ^ ((v * np.uint64(0x53A22864)) & _MASK)
    return reverse_bits(v)


def sobol_set(index: np.ndarray, seeds: np.ndarray) -> np.ndarray:
    """Points ``(N, 2)`` in [0, 1)² of the scrambled two-dimensional Sobol' sequence: its points
    ``index (N,)`` (:func:`sobol_points`), each dimension scrambled by its column of ``seeds (N,
    2)`` (32-bit integers, :func:`owen_scramble`), times 2^-32. Indices 0 .. 2^m - 1 with one
    pair of seeds are a (0, m, 2)-net (the module page); the renderer gives every pixel and
    pair of dimensions seeds of their own (:mod:`raykit.engine.noise`)."""
    points = sobol_points(index)
    seeds = np.asarray(seeds).astype(np.uint64).reshape(-1, 2)
    x = owen_scramble(points[:, 0], seeds[:, 0])
    y = owen_scramble(points[:, 1], seeds[:, 1])
    return np.column_stack([x, y]).astype(np.float64) * 2.0**-SOBOL_BITS

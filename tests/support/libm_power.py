"""The reference's highlight with the C library's pow: the one operation the two engines do
differently (raykit.engine.compiled's docstring). numpy's vectorised power and the C library's
pow, which the compiled engine calls, differ in the last place on a few per cent of inputs on
some processors; with this, the reference's colours are the compiled engine's bit for bit.
Used by tests/compiled/ and benchmarks/engine_agreement.py."""

from __future__ import annotations

import contextlib
import math

import numpy as np

from raykit import shading
from raykit.rays import dot, normalize

_libm_pow = np.frompyfunc(math.pow, 2, 1)


def _blinn_phong_with_libm_pow(ks, intensity, n, l, v, p):  # FOCG's letters
    """raykit.shading.blinn_phong with the C library's pow in place of numpy's power."""
    h = normalize(l + v)
    power = _libm_pow(np.maximum(0.0, dot(n, h)), p).astype(float)
    return ks * intensity * power[:, None]


@contextlib.contextmanager
def libm_power():
    """The reference's highlight with the C library's pow, while inside."""
    original = shading.blinn_phong
    shading.blinn_phong = _blinn_phong_with_libm_pow
    try:
        yield
    finally:
        shading.blinn_phong = original

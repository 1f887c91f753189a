"""Exact answers for the tests: rational arithmetic on the very floats a test uses."""

from __future__ import annotations

from fractions import Fraction


def exact_sphere_hit(origin, direction, center, radius) -> bool:
    """Whether the ray o + t·d (t > 0) meets the sphere, decided exactly (every float is a
    rational): the discriminant b'² - a·c' >= 0, and the sphere ahead (b' < 0) or around the
    origin (c' < 0)."""
    f = [Fraction(float(o)) - Fraction(float(c)) for o, c in zip(origin, center, strict=True)]
    d = [Fraction(float(x)) for x in direction]
    a = sum(x * x for x in d)
    b = sum(x * y for x, y in zip(f, d, strict=True))
    c = sum(x * x for x in f) - Fraction(float(radius)) ** 2
    return b * b - a * c >= 0 and (b < 0 or c < 0)

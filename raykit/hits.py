"""The nearest hit so far, per ray: the bookkeeping of every "nearest hit wins" loop.

The 3D renderer (:func:`raykit.render.cast`) and the line-scan tracer
(:func:`raykit.linescan.scan.trace`) both go through their objects in index order and offer each
object's hits to :meth:`Hits.keep_nearer`; what stays is, per ray, the nearest hit with t > 0.
Ties keep the object offered first (a strict ``<``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from raykit.rays import MISS

# Given the indices (M,) of the rays an object would be nearest for, its colours there (M, 3)
# and whether it is opaque there (M,) bool: False is a hole (a cut-out texel) the ray goes past.
ColorAt = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


@dataclass
class Hits:
    """Per ray: ``index (N,)`` of the nearest object (-1 none), its ``t (N,)`` (``MISS`` none)
    and ``color (N, 3)`` (the background where nothing was hit)."""

    index: np.ndarray
    t: np.ndarray
    color: np.ndarray

    @classmethod
    def none(cls, n: int, background: np.ndarray) -> Hits:
        """N rays that have hit nothing yet."""
        color = np.broadcast_to(np.asarray(background, float), (n, 3)).copy()
        return cls(np.full(n, -1), np.full(n, MISS), color)

    def keep_nearer(self, index: int, t: np.ndarray, color_at: ColorAt) -> None:
        """Object ``index``, hit at ``t (N,)``, becomes the nearest where it is nearer and opaque.

        ``color_at`` is asked only about the rays where it is nearer, so a texture is read only
        where it can be seen.
        """
        # BEGIN SOLUTION
        # hint: where t < self.t and the object is opaque there, store t, the index and the colour
        nearer = np.flatnonzero(t < self.t)
        if len(nearer) == 0:  # nothing to ask: a texture nobody sees stays undecoded
            return
        colors, opaque = color_at(nearer)
        nearer = nearer[opaque]
        self.t[nearer] = t[nearer]
        self.index[nearer] = index
        self.color[nearer] = colors[opaque]
        # END SOLUTION


def solid(color: np.ndarray) -> ColorAt:
    """The ``color_at`` of an object with one colour ``(3,)`` and no holes."""
    color = np.asarray(color, float)

    def color_at(rays: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return np.broadcast_to(color, (len(rays), 3)), np.ones(len(rays), dtype=bool)

    return color_at

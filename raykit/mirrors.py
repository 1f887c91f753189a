"""Mirror reflection (FOCG 4.8): what a mirror shows is what its reflected ray sees.

A ray with unit direction d meets a mirror with unit normal n. The reflected ray leaves the
hit point with

    r = d - 2(d·n)n,

the direction d with its component along n turned round (r is unit length too, and it does not
matter which way n points). Its colour, weighted by the mirror reflectance km, adds to the
surface's own: L = L_surface + km·L(r). A mirror ray that meets another mirror is reflected
again, up to the scene's ``max_depth`` bounces; after the last one the mirror adds nothing.

Like a shadow ray, a mirror ray starts a little off the surface
(:meth:`raykit.surfaces.SurfacePoints.start`).
"""

from __future__ import annotations

import numpy as np

from raykit.rays import dot


def reflect(d: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Mirror directions r = d - 2(d·n)n ``(N, 3)`` of unit directions ``d`` at unit normals
    ``n``, both ``(N, 3)``."""
    # BEGIN SOLUTION
    # hint: r = d - 2(d·n)n, row by row (raykit.rays.dot gives d·n for every row)
    return d - 2.0 * dot(d, n)[:, None] * n
    # END SOLUTION

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

Glossy reflection (stage 5, FOCG 13.4.4). A glossy mirror of glossiness a (the side of FOCG's
square; 0 is the ideal mirror) reflects each ray along its own direction r', r moved within the
square of side a perpendicular to it (:func:`raykit.sampling.perturbed_direction`), from the
ray's own uniform numbers; the blur is the mean over a pixel's samples. A perturbed r' may
point below the surface (r'·n on the side the ray came from): FOCG treats such a ray as
absorbed, and so does raykit: it reflects nothing, black, and still counts in the pixel's mean
(:func:`glossy_reflect`). With a = 0 the mirror's ray is r itself, bit for bit.
"""

from __future__ import annotations

import numpy as np

from raykit.rays import dot
from raykit.sampling import perturbed_direction


def reflect(d: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Mirror directions r = d - 2(d·n)n ``(N, 3)`` of unit directions ``d`` at unit normals
    ``n``, both ``(N, 3)``."""
    # BEGIN SOLUTION
    # hint: r = d - 2(d·n)n, row by row (raykit.rays.dot gives d·n for every row)
    return d - 2.0 * dot(d, n)[:, None] * n
    # END SOLUTION


def glossy_reflect(
    d: np.ndarray, n: np.ndarray, a: np.ndarray, uniforms: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Glossy mirror directions r' ``(N, 3)`` of unit directions ``d`` at unit normals ``n``
    ``(N, 3)``, each the mirror direction r = :func:`reflect` moved within the square of side
    ``a (N,)`` (the row's glossiness) by :func:`raykit.sampling.perturbed_direction` with
    ``uniforms (N, 2)``, and ``(N,)`` bool: r' leaves above the surface, on the side d came from
    (r'·n of the other sign than d·n). A row with a = 0 is the ideal mirror: r itself, always
    above. Where r' is not above, the ray is absorbed (FOCG 13.4.4; the module page)."""
    # BEGIN SOLUTION
    # hint: r = reflect(d, n); perturb it with a as a column (a[:, None]); keep r where a = 0;
    #       above where r'·n and d·n have opposite signs
    r = reflect(d, n)
    a = np.asarray(a, dtype=float)
    glossy = a > 0
    r_prime = np.where(glossy[:, None], perturbed_direction(r, a[:, None], uniforms), r)
    above = ~glossy | (np.sign(dot(r_prime, n)) == -np.sign(dot(d, n)))
    return r_prime, above
    # END SOLUTION

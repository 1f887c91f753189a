"""Surface points: where rays hit, the normal there, and where a secondary ray starts from.

Shading (:mod:`raykit.shading`) works on the hit points of many rays at once. For each it needs

* the point p = o + t·d (:func:`raykit.rays.point_at`);
* the unit normal n there, pointing out of the surface: (p - c)/r on a sphere
  (:func:`raykit.spheres.sphere_normals`); on a billboard, which has two sides, the side facing
  the ray's origin (:func:`raykit.billboards.billboard_normals`);
* how far the computed p may lie from the true surface, ``error``.

Why secondary rays start off the surface
----------------------------------------
A shadow ray or a mirror ray starts at p. But p was rounded: it lies a little in front of or
behind the true surface, so a ray started there may hit the surface it starts on at a tiny
t > 0 and call the point shadowed ("shadow acne", a speckle of dark pixels). So a secondary ray
starts at p + ε·n, moved off the surface along the normal, to the side it leaves towards.

ε must exceed the rounding error of p, and that error grows with the numbers that made p: p is
o + t·d, so each coordinate is off by a few units in the last place of max(|o|, t·|d|) (the
stable intersection forms keep t's own error to a few units in its last place). With unit
directions that is

    error = eps · (max_i |o_i| + t),    ε = OFFSET_FACTOR · error,

with eps the float type's machine epsilon (2.2e-16 for float64, 1.2e-7 for float32). A fixed
ε (the classic 1e-4) fails both ways: at coordinates near 1e6 in float32, or 1e13 in float64,
rounding exceeds it and acne returns; in a small scene it is large enough to let light leak
through thin gaps. Scaled with the coordinates, ε stays a fixed number of float steps above the
error at any size: in a scene at 1e6 in float64 it is about 4e-9, far below any feature.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from raykit.billboards import billboard_normals
from raykit.rays import dot, point_at
from raykit.scene import Scene
from raykit.spheres import sphere_normals

OFFSET_FACTOR = 16  # ε in units of the error bound; 1 was already acne-free in the tests


@dataclass(frozen=True)
class SurfacePoints:
    """N hit points: ``points (N, 3)``, unit ``normals (N, 3)``, ``error (N,)``."""

    points: np.ndarray
    normals: np.ndarray
    error: np.ndarray

    def start(self, directions: np.ndarray) -> np.ndarray:
        """Origins ``(N, 3)`` for secondary rays leaving along ``directions (N, 3)``: each point
        moved ε along the normal, to the side the ray leaves towards (see the module page)."""
        side = np.where(dot(self.normals, directions) >= 0, 1.0, -1.0)
        epsilon = OFFSET_FACTOR * self.error
        return self.points + (side * epsilon)[:, None] * self.normals

    def take(self, rows: np.ndarray) -> SurfacePoints:
        """The surface points of the given rows only."""
        return SurfacePoints(self.points[rows], self.normals[rows], self.error[rows])


def surface_points(
    scene: Scene,
    origins: np.ndarray,
    directions: np.ndarray,
    t: np.ndarray,
    index: np.ndarray,
    times: np.ndarray | None = None,
) -> SurfacePoints:
    """Where rays ``(N, 3)`` hit objects ``index (N,)`` (each >= 0) at ``t (N,)``; directions
    must be unit length (as the camera's, shadow and mirror rays are). ``times (N,)``: the
    rays' times, where a moving sphere is (motion blur; None: the spheres as they stand)."""
    points = point_at(origins, directions, t)
    normals = np.empty_like(points)
    spheres = len(scene.spheres)
    on_sphere = np.flatnonzero(index < spheres)
    if len(on_sphere):
        hit = np.unique(index[on_sphere])  # the spheres hit, in index order
        centers = np.stack([np.asarray(scene.spheres[i].center) for i in hit])
        radii = np.array([scene.spheres[i].radius for i in hit])
        which = np.searchsorted(hit, index[on_sphere])
        if times is not None and scene.velocities is not None:  # each centre at its ray's time
            centers = centers[which] + times[on_sphere][:, None] * scene.velocities[hit[which]]
            radii, which = radii[which], np.arange(len(on_sphere))
        normals[on_sphere] = sphere_normals(
            points[on_sphere], centers[which], radii[which][:, None]
        )
    for i in np.unique(index[index >= spheres]):
        on = np.flatnonzero(index == i)
        normals[on] = billboard_normals(scene.billboards[i - spheres], directions[on])
    eps = np.finfo(np.result_type(origins, directions)).eps  # the float type t was found in
    error = eps * (np.abs(origins).max(axis=1) + t)
    return SurfacePoints(points, normals, error)

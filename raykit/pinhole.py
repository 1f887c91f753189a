"""The pinhole camera, and the camera obscura it simplifies.

In a camera obscura light from the scene passes through a small hole and lands on the wall
*behind* it: every ray crosses at the hole, so the picture on the wall is upside down and
mirrored (turned half a turn). The ray tracer's pinhole camera (:mod:`raykit.camera`) puts the
image plane the same distance d *in front* of the hole instead, where the same rays give an
upright picture: the simplification the lecture makes.

:func:`obscura_rays` makes the obscura's rays with the camera's own frame and image-plane
mapping: the wall's pixel (x, y) sits at eye + d·w + s·u + t·v (behind the eye, w pointing
backwards), and its ray leaves the hole e toward the scene, away from the wall. Rendered with the
renderer's own casting, the wall's picture is the pinhole render turned half a turn (tested).
"""

from __future__ import annotations

import numpy as np

from raykit.camera import Camera, region_points
from raykit.hits import Hits
from raykit.rays import normalize
from raykit.render import cast


def obscura_rays(camera: Camera, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The camera obscura's rays for wall points (x, y) ``(N,)`` (image coordinates as in
    :mod:`raykit.camera`): ``origins (N, 3)``, all at the hole e, and unit ``directions
    (N, 3)`` from the wall point through the hole, e - (e + d·w + s·u + t·v)."""
    u, v, w = camera.frame
    Wp, Hp = camera.plane_size
    s = -Wp / 2 + np.asarray(x, float) * (Wp / camera.width)
    t = Hp / 2 - np.asarray(y, float) * (Hp / camera.height)
    wall_from_eye = camera.d * w + s[:, None] * u + t[:, None] * v  # behind the hole
    origins = np.broadcast_to(np.asarray(camera.eye, float), wall_from_eye.shape).copy()
    return origins, normalize(-wall_from_eye)


def render_obscura(scene) -> Hits:
    """The picture on the obscura's back wall, ``Hits`` of one ray per wall pixel centre,
    row-major ``(H·W,)``: flat colours (:func:`raykit.render.cast`)."""
    camera = scene.camera
    x, y = region_points(range(camera.height), range(camera.width))
    return cast(scene, *obscura_rays(camera, x, y))

"""Screen-space bounds: the part of the image in which an object can be seen at all.

For each object, a rectangle ``(x0, x1, y0, y1)`` in continuous image coordinates (x along
columns, y down rows, as in :mod:`raykit.camera`) that contains every image point whose ray can
hit the object, or ``None`` when no ray can (it lies behind the eye, or off the image). The
renderer's tiles (:mod:`raykit.tiles`) use them to skip objects that cannot be hit in a tile.

The rectangles are conservative, never tight at the cost of a pixel:

* a sphere in front of the eye: the planes through the eye (perspective) tangent to the sphere
  give its exact extent along u and along v; orthographic, its centre ± r;
* a billboard in front of the eye: the box around its four projected corners (the projection of
  a flat convex shape is the hull of its projected corners);
* an object that reaches the plane through the eye (perpendicular to w), where projection
  breaks down: the whole image;
* then one pixel of margin on every side, against rounding.

Depth here is the distance in front of the eye along -w; a ray's points with t > 0 all have
depth > 0, so an object entirely at depth <= 0 can never be hit.
"""

from __future__ import annotations

import numpy as np

from raykit.billboards import Billboard
from raykit.camera import Camera
from raykit.spheres import Sphere

MARGIN = 1.0  # pixels
Bounds = tuple[float, float, float, float]


def _camera_coordinates(camera: Camera, points: np.ndarray) -> np.ndarray:
    """Points ``(N, 3)`` as (along u, along v, depth along -w) relative to the eye."""
    u, v, w = camera.frame
    relative = np.asarray(points, float) - np.asarray(camera.eye, float)
    return np.stack([relative @ u, relative @ v, -(relative @ w)], axis=-1)


def _to_image(camera: Camera, s: np.ndarray, t: np.ndarray) -> Bounds | None:
    """Image-plane extents [s] x [t] as a clipped, margined pixel rectangle (None if off)."""
    Wp, Hp = camera.plane_size
    x0 = (s.min() + Wp / 2) * camera.width / Wp - MARGIN
    x1 = (s.max() + Wp / 2) * camera.width / Wp + MARGIN
    y0 = (Hp / 2 - t.max()) * camera.height / Hp - MARGIN
    y1 = (Hp / 2 - t.min()) * camera.height / Hp + MARGIN
    if x1 < 0 or y1 < 0 or x0 > camera.width or y0 > camera.height:
        return None
    return (max(x0, 0.0), min(x1, float(camera.width)), max(y0, 0.0), min(y1, float(camera.height)))


def _whole_image(camera: Camera) -> Bounds:
    return (0.0, float(camera.width), 0.0, float(camera.height))


def _tangent_slopes(across: float, depth: float, radius: float) -> np.ndarray:
    """Slopes m = across/depth of the two lines through the eye tangent to a circle."""
    root = radius * np.sqrt(max(across * across + depth * depth - radius * radius, 0.0))
    return (across * depth + np.array([-root, root])) / (depth * depth - radius * radius)


def sphere_bounds(camera: Camera, sphere: Sphere) -> Bounds | None:
    """The screen rectangle of a sphere (see the module docstring)."""
    x, y, depth = _camera_coordinates(camera, np.asarray(sphere.center)[None])[0]
    r = float(sphere.radius)
    if depth < -r:
        return None  # wholly behind the eye
    if camera.projection == "orthographic":
        return _to_image(camera, np.array([x - r, x + r]), np.array([y - r, y + r]))
    if depth <= r * (1 + 1e-9):
        return _whole_image(camera)  # reaches the eye's plane (or holds the eye)
    return _to_image(
        camera, camera.d * _tangent_slopes(x, depth, r), camera.d * _tangent_slopes(y, depth, r)
    )


def billboard_bounds(camera: Camera, billboard: Billboard) -> Bounds | None:
    """The screen rectangle of a billboard (see the module docstring)."""
    ul = np.asarray(billboard.upper_left, float)
    corners = np.stack([ul, ul + billboard.a, ul + billboard.b, ul + billboard.a + billboard.b])
    x, y, depth = _camera_coordinates(camera, corners).T
    if (depth <= 0).all():
        return None  # wholly behind the eye
    if camera.projection == "orthographic":
        return _to_image(camera, x, y)
    scale = np.abs(corners - camera.eye).max()
    if (depth <= 1e-9 * scale).any():
        return _whole_image(camera)  # crosses the eye's plane
    return _to_image(camera, camera.d * x / depth, camera.d * y / depth)


def object_bounds(camera: Camera, objects) -> np.ndarray:
    """Bounds of every object, ``(K, 4)`` rows (x0, x1, y0, y1); NaN rows for never visible."""
    rows = []
    for obj in objects:
        found = (
            sphere_bounds(camera, obj) if isinstance(obj, Sphere) else billboard_bounds(camera, obj)
        )
        rows.append(found if found is not None else (np.nan,) * 4)
    return np.array(rows, dtype=float).reshape(-1, 4)

"""Screen-space bounds: the part of the image in which an object can be seen at all.

For each object, a rectangle ``(x0, x1, y0, y1)`` in continuous image coordinates (x along
columns, y down rows, as in :mod:`raykit.camera`) that contains every image point whose ray can
hit the object, or ``None`` when no ray can (it lies behind the eye, or off the image). The
renderer's tiles (:mod:`raykit.engine.tiles`) use them to skip objects that cannot be hit in a tile.

The rectangles are conservative, never tight at the cost of a pixel:

* a sphere in front of the eye: the planes through the eye (perspective) tangent to the sphere
  give its exact extent along u and along v; orthographic, its centre ± r;
* a billboard in front of the eye: the box around its four projected corners (the projection of
  a flat convex shape is the hull of its projected corners);
* an object that reaches the plane through the eye (perpendicular to w), where projection
  breaks down: the whole image;
* then a margin of MARGIN pixels on every side, against rounding. The rectangles and the rays
  are each computed to about 1e-12 of a pixel (double precision; far tiny spheres and scenes at
  1e6 included), so a thousandth of a pixel is ample; it is small so that a sphere smaller than
  a pixel is tested only by the pixels whose centres it may cover (a whole pixel of margin had
  every such sphere tested by four to nine).

Depth here is the distance in front of the eye along -w; a ray's points with t > 0 all have
depth > 0, so an object entirely at depth <= 0 can never be hit.
"""

from __future__ import annotations

import numpy as np

from raykit.billboards import Billboard
from raykit.camera import Camera
from raykit.rays import dot
from raykit.spheres import Sphere

MARGIN = 1e-3  # pixels
Bounds = tuple[float, float, float, float]


def _camera_coordinates(camera: Camera, points: np.ndarray) -> np.ndarray:
    """Points ``(N, 3)`` as (along u, along v, depth along -w) relative to the eye."""
    u, v, w = camera.frame
    relative = np.asarray(points, float) - np.asarray(camera.eye, float)
    return np.stack([dot(relative, u), dot(relative, v), -dot(relative, w)], axis=-1)


def _whole_image(camera: Camera) -> Bounds:
    return (0.0, float(camera.width), 0.0, float(camera.height))


def _tangent_slopes(
    across: np.ndarray, depth: np.ndarray, radius: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Slopes m = across/depth ``(S,)`` of the two lines through the eye tangent to circles."""
    root = radius * np.sqrt(np.maximum(across * across + depth * depth - radius * radius, 0.0))
    below = depth * depth - radius * radius
    return (across * depth - root) / below, (across * depth + root) / below


def spheres_bounds(camera: Camera, centers: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """Screen rectangles of S spheres at once (see the module docstring), ``(S, 4)`` rows
    (x0, x1, y0, y1); NaN rows for spheres never visible."""
    x, y, depth = _camera_coordinates(camera, np.asarray(centers, float).reshape(-1, 3)).T
    r = np.asarray(radii, float)
    bounds = np.full((len(r), 4), np.nan)
    seen = depth >= -r  # else wholly behind the eye
    if camera.projection == "orthographic":
        extents = (x - r, x + r, y - r, y + r)
    else:
        whole = seen & (depth <= r * (1 + 1e-9))  # reaches the eye's plane (or holds the eye)
        bounds[whole] = _whole_image(camera)
        seen &= ~whole
        with np.errstate(divide="ignore", invalid="ignore"):
            s_low, s_high = _tangent_slopes(x, depth, r)
            t_low, t_high = _tangent_slopes(y, depth, r)
        extents = tuple(camera.d * m for m in (s_low, s_high, t_low, t_high))
    bounds[seen] = _to_image_rows(camera, *(e[seen] for e in extents))
    return bounds


def _to_image_rows(
    camera: Camera, s0: np.ndarray, s1: np.ndarray, t0: np.ndarray, t1: np.ndarray
) -> np.ndarray:
    """Image-plane extents [s0, s1] x [t0, t1] ``(S,)`` as clipped, margined pixel rectangles
    ``(S, 4)``, NaN rows for those off the image."""
    Wp, Hp = camera.plane_size
    x0 = (s0 + Wp / 2) * camera.width / Wp - MARGIN
    x1 = (s1 + Wp / 2) * camera.width / Wp + MARGIN
    y0 = (Hp / 2 - t1) * camera.height / Hp - MARGIN
    y1 = (Hp / 2 - t0) * camera.height / Hp + MARGIN
    rows = np.column_stack(
        [
            np.maximum(x0, 0.0),
            np.minimum(x1, float(camera.width)),
            np.maximum(y0, 0.0),
            np.minimum(y1, float(camera.height)),
        ]
    )
    off = (x1 < 0) | (y1 < 0) | (x0 > camera.width) | (y0 > camera.height)
    rows[off] = np.nan
    return rows


def sphere_bounds(camera: Camera, sphere: Sphere) -> Bounds | None:
    """The screen rectangle of one sphere, or None (see :func:`spheres_bounds`)."""
    row = spheres_bounds(camera, np.asarray(sphere.center)[None], np.array([sphere.radius]))[0]
    return None if np.isnan(row).any() else tuple(float(v) for v in row)


def billboard_bounds(camera: Camera, billboard: Billboard) -> Bounds | None:
    """The screen rectangle of one billboard, or None (see :func:`billboards_bounds`)."""
    row = billboards_bounds(camera, [billboard])[0]
    return None if np.isnan(row).any() else tuple(float(v) for v in row)


def billboards_bounds(camera: Camera, billboards) -> np.ndarray:
    """Screen rectangles of B billboards at once (see the module docstring), ``(B, 4)`` rows
    (x0, x1, y0, y1); NaN rows for billboards never visible."""
    bounds = np.full((len(billboards), 4), np.nan)
    if not billboards:
        return bounds
    ul = np.array([np.asarray(board.upper_left, float) for board in billboards])
    a = np.array([board.a for board in billboards], float)
    b = np.array([board.b for board in billboards], float)
    corners = np.stack([ul, ul + a, ul + b, ul + a + b], axis=1)  # (B, 4, 3)
    x, y, depth = np.moveaxis(_camera_coordinates(camera, corners), -1, 0)  # each (B, 4)
    seen = ~(depth <= 0).all(axis=1)  # else wholly behind the eye
    if camera.projection == "orthographic":
        s, t = x, y
    else:
        scale = np.abs(corners - camera.eye).max(axis=(1, 2))
        whole = seen & (depth <= 1e-9 * scale[:, None]).any(axis=1)  # crosses the eye's plane
        bounds[whole] = _whole_image(camera)
        seen &= ~whole
        with np.errstate(divide="ignore", invalid="ignore"):
            s, t = camera.d * x / depth, camera.d * y / depth
    rows = _to_image_rows(camera, s.min(axis=1), s.max(axis=1), t.min(axis=1), t.max(axis=1))
    bounds[seen] = rows[seen]
    return bounds


def scene_bounds(camera: Camera, centers: np.ndarray, radii: np.ndarray, billboards) -> np.ndarray:
    """Bounds of a scene's K objects in index order, the spheres (``centers (S, 3)``, ``radii
    (S,)``, :func:`spheres_bounds`) then the billboards (:func:`billboards_bounds`): ``(K, 4)``
    rows (x0, x1, y0, y1); NaN rows for never visible."""
    bounds = np.full((len(radii) + len(billboards), 4), np.nan)
    if len(radii):
        bounds[: len(radii)] = spheres_bounds(camera, centers, radii)
    bounds[len(radii) :] = billboards_bounds(camera, billboards)
    return bounds


def object_bounds(camera: Camera, objects) -> np.ndarray:
    """Bounds of every object of ``objects`` (spheres and billboards in any order): ``(K, 4)``
    rows as :func:`scene_bounds` gives them."""
    spheres = [obj for obj in objects if isinstance(obj, Sphere)]
    boards = [obj for obj in objects if not isinstance(obj, Sphere)]
    centers = np.array([s.center for s in spheres], dtype=float).reshape(-1, 3)
    radii = np.array([s.radius for s in spheres], dtype=float)
    found = scene_bounds(camera, centers, radii, boards)
    is_sphere = np.array([isinstance(obj, Sphere) for obj in objects], dtype=bool)
    bounds = np.empty((len(objects), 4))
    bounds[is_sphere] = found[: len(spheres)]
    bounds[~is_sphere] = found[len(spheres) :]
    return bounds

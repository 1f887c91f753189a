"""The 3D camera: the u, v, w frame, the image plane, and one ray per pixel sample.

Conventions (owned here; every other 3D module refers to this page)
-------------------------------------------------------------------
* Frame: w = normalize(eye - lookat) points *backwards*, from what we look at to the eye;
  u = normalize(up × w) points to the right of the image; v = w × u points up the image.
  (u, v, w) is right-handed and orthonormal; ``up`` need only not be parallel to w: it is
  not necessarily v, but lies in the same plane as v and w (v is up with its part along w
  taken away).
* Image plane: it passes through lookat, at distance d = |lookat - eye| from the eye, and is
  Hp = 2·d·tan(fov_angle / 2) high and Wp = Hp·width / height wide. ``fov_angle`` is the
  *vertical* field of view, in degrees. In the camera's own coordinates (eye at 0, axes
  u, v, w) the plane is w = -d: the slide's question "What should w be?" has that answer,
  since the camera looks along -w.
* Two d's. The slides say "from now on, we use d to denote distance to image plane"
  (``Camera.d`` here),
  while a ray's direction is also d (p(t) = o + t·d, :mod:`raykit.rays`). They never meet in
  one formula; in code the distance is always ``camera.d`` and a direction a plain ``d``
  array of rays.
* Pixels: row r counts from the *top* of the image (row 0 is the top row, as in the PNG and in
  numpy's ``image[r, c]``), column c from the left. A point inside pixel (r, c) has continuous
  image coordinates x = c + a, y = r + b with the sample offset (a, b) in [0, 1)²; the pixel
  centre is (a, b) = (0.5, 0.5). The image-plane point is

      s = -Wp/2 + x·Wp/width,   t = Hp/2 - y·Hp/height,   P = eye - d·w + s·u + t·v.

* Perspective: origin e = eye, direction P - eye = -d·w + s·u + t·v (formed without subtracting
  eye, so a camera at 1e6 loses no digits). The slide's ray is p(t) = e + t(s - e) with its s
  = our P: then t = 1 on the image plane. raykit scales the direction to unit length instead,
  so that the ray parameter is the distance from the eye: hits of different rays, and of
  shadow and mirror rays, compare in one unit, and the sphere's A = d·d is 1. (The letters:
  the slide's s is P here; our s and t are P's coordinates along u and v.)
* Orthographic: origin eye + s·u + t·v, direction -w: parallel rays that frame the plane
  through lookat exactly as the perspective camera does.
* Thin lens (stage 5, FOCG 13.4.3): a perspective camera with an ``aperture`` > 0 has a lens,
  the disk of radius aperture/2 around the eye in the u, v plane (the aperture is its
  *diameter*), and sees sharp only the focal plane, at ``focus_distance`` f in front of the eye
  (w = -f; by default f = d, the plane through lookat). A ray of image point P starts at its
  own point r = e + (aperture/2)·(x·u + y·v) of the lens ((x, y) in the unit disk,
  :func:`raykit.sampling.point_on_lens`) and aims at the point where the pinhole ray of P meets
  the focal plane, s = e + (f/d)·(P - e): every ray of P meets there, so what lies on the focal
  plane stays sharp, and the farther a point from it, the wider the disk it is spread over.
  Aperture 0 is the pinhole, and renders with :func:`rays_through` itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from raykit.rays import length, normalize
from raykit.sampling import point_on_lens

PROJECTIONS = ("perspective", "orthographic")


class DegenerateFrameError(ValueError):
    """No camera frame exists; ``culprit`` names the input to change ("lookat" or "up")."""

    def __init__(self, culprit: str, problem: str) -> None:
        self.culprit = culprit
        super().__init__(problem)


@dataclass(frozen=True)
class Camera:
    """Where the eye is, what it looks at, and the image it takes (see the module conventions)."""

    eye: np.ndarray
    lookat: np.ndarray
    up: np.ndarray
    fov_angle: float
    width: int
    height: int
    projection: str = "perspective"
    aperture: float = 0.0  # the thin lens's diameter; 0: the pinhole
    focus_distance: float | None = None  # to the focal plane; None: d, the plane through lookat

    @property
    def focus(self) -> float:
        """f, the distance from the eye to the focal plane (``focus_distance``, or d)."""
        return self.d if self.focus_distance is None else float(self.focus_distance)

    @cached_property
    def frame(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The orthonormal camera frame (u, v, w), each ``(3,)``."""
        return camera_frame(self.eye, self.lookat, self.up)

    @cached_property
    def d(self) -> float:
        """Distance from the eye to the image plane, |lookat - eye|."""
        return float(length(np.asarray(self.lookat, float) - np.asarray(self.eye, float)))

    @property
    def plane_size(self) -> tuple[float, float]:
        """(Wp, Hp): width and height of the image plane, in scene units."""
        Hp = 2.0 * self.d * math.tan(math.radians(self.fov_angle) / 2.0)
        return Hp * self.width / self.height, Hp


def camera_frame(
    eye: np.ndarray, lookat: np.ndarray, up: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The frame (u, v, w) of the conventions above; :class:`DegenerateFrameError` if none exists.

    Raises when eye == lookat (no view direction) or when up is zero or parallel to w.
    """
    # BEGIN SOLUTION
    # hint: w = normalize(eye - lookat), u = normalize(up × w), v = w × u; raise
    #       DegenerateFrameError when there is no frame
    eye, lookat, up = (np.asarray(x, dtype=float) for x in (eye, lookat, up))
    backwards = eye - lookat
    if not np.any(backwards):
        raise DegenerateFrameError(
            "lookat", "is the same point as eye, so there is no view direction"
        )
    w = normalize(backwards)
    if not np.any(up):
        raise DegenerateFrameError("up", "is the zero vector")
    up_cross_w = np.cross(up, w)
    if length(up_cross_w) <= 1e-12 * length(up):
        raise DegenerateFrameError(
            "up", "is parallel to the view direction, so it fixes no image rotation"
        )
    u = normalize(up_cross_w)
    v = np.cross(w, u)
    return u, v, w
    # END SOLUTION


def sample_offsets(samples: int) -> np.ndarray:
    """The n x n sample offsets (a, b) inside a pixel, ``(n*n, 2)``: a regular grid of sub-pixel
    centres, so n = 1 gives the pixel centre (0.5, 0.5) and odd n always includes it."""
    if samples < 1:
        raise ValueError(f"samples must be >= 1, got {samples}")
    centres = (np.arange(samples) + 0.5) / samples
    a, b = np.meshgrid(centres, centres, indexing="xy")
    return np.column_stack([a.ravel(), b.ravel()])


def centre_sample(samples: int) -> int | None:
    """Which of the n x n :func:`sample_offsets` is the pixel centre (0.5, 0.5): the middle one
    for odd n, none for even n."""
    return samples // 2 * (samples + 1) if samples % 2 else None


def image_plane_points(camera: Camera, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The points P = eye - d·w + s·u + t·v ``(N, 3)`` of continuous image points (x, y)."""
    u, v, w = camera.frame
    return np.asarray(camera.eye, float) - camera.d * w + _in_plane(camera, x, y)


def image_plane_corners(camera: Camera) -> np.ndarray:
    """The image plane's corners ``(4, 3)``: upper left, upper right, lower right, lower left."""
    width, height = camera.width, camera.height
    return image_plane_points(
        camera, np.array([0, width, width, 0]), np.array([0, 0, height, height])
    )


def rays_through(camera: Camera, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rays through continuous image points (x along columns, y down rows), ``(N,)`` each.

    Returns ``origins (N, 3)`` and unit ``directions (N, 3)``. Pixel (r, c) sampled at offset
    (a, b) is x = c + a, y = r + b.
    """
    # BEGIN SOLUTION
    # hint: perspective: origin eye, direction normalize(s·u + t·v - d·w); orthographic: origin eye
    #       + s·u + t·v, direction -w
    u, v, w = camera.frame
    in_plane = _in_plane(camera, x, y)
    eye = np.asarray(camera.eye, dtype=float)
    if camera.projection == "orthographic":
        origins = eye + in_plane
        directions = np.broadcast_to(-w, origins.shape).copy()
    else:
        origins = np.broadcast_to(eye, in_plane.shape).copy()
        directions = normalize(in_plane - camera.d * w)
    return origins, directions
    # END SOLUTION


def thin_lens_rays(
    camera: Camera, x: np.ndarray, y: np.ndarray, uniforms: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Thin-lens rays (FOCG 13.4.3) through continuous image points (x, y) ``(N,)``, each from
    its own point on the lens chosen by ``uniforms (N, 2)``: ``origins (N, 3)`` r on the lens,
    unit ``directions (N, 3)`` toward s = e + (f/d)·(P - e) on the focal plane (module
    conventions). Perspective cameras only. A stage-5 student function."""
    # BEGIN SOLUTION
    # hint: r = point_on_lens(eye, u, v, aperture, uniforms); the pinhole ray's P - e is
    #       _in_plane(x, y) - d·w, which meets the focal plane at s = e + (f/d)·(P - e)
    #       (f = camera.focus); origins r, directions normalize(s - r), both formed
    #       relative to the eye (as rays_through does)
    u, v, w = camera.frame
    eye = np.asarray(camera.eye, dtype=float)
    pinhole = _in_plane(camera, x, y) - camera.d * w  # P - e, the pinhole ray's direction
    on_lens = point_on_lens(np.zeros(3), u, v, camera.aperture, uniforms)  # r - e
    # relative to the eye, as rays_through forms its directions: a camera far from the
    # origin keeps its digits
    directions = normalize((camera.focus / camera.d) * pinhole - on_lens)
    return eye + on_lens, directions
    # END SOLUTION


def _in_plane(camera: Camera, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """s·u + t·v ``(N, 3)``: where (x, y) lies on the image plane, from its centre."""
    # BEGIN SOLUTION
    # hint: s = -Wp/2 + x·Wp/width, t = Hp/2 - y·Hp/height; return s·u + t·v, shape (N, 3)
    u, v, _ = camera.frame
    Wp, Hp = camera.plane_size
    s = -Wp / 2 + np.asarray(x, dtype=float) * (Wp / camera.width)
    t = Hp / 2 - np.asarray(y, dtype=float) * (Hp / camera.height)
    return s[:, None] * u + t[:, None] * v
    # END SOLUTION


def pixel_points(
    width: int, rows: range, a: float = 0.5, b: float = 0.5
) -> tuple[np.ndarray, np.ndarray]:
    """Continuous image coordinates (x, y) ``(len(rows)*width,)`` of one sample in every pixel
    of the given rows, in row-major order (the order of ``image[rows].reshape(-1, 3)``)."""
    return region_points(rows, range(width), a, b)


def region_points(
    rows: range, cols: range, a: float = 0.5, b: float = 0.5
) -> tuple[np.ndarray, np.ndarray]:
    """Continuous image coordinates (x, y) ``(len(rows)*len(cols),)`` of one sample, at offset
    (a, b), in every pixel of rows x cols, row-major."""
    x = np.tile(np.asarray(cols, dtype=float) + a, len(rows))
    y = np.repeat(np.asarray(rows, dtype=float) + b, len(cols))
    return x, y

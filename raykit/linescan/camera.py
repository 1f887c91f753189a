"""The 2D line-scan camera: an eye, a view direction, and one line of N pixels.

Conventions (owned here; every line-scan module refers to this page)
--------------------------------------------------------------------
* The world is the plane with x to the right and y up, seen from above.
* ``e`` is the eye, ``w`` the view direction (any length; it is scaled to unit length).
* u is w turned a quarter turn to the *left* (counter-clockwise): u = (-w_y, w_x). Standing at
  e and looking along w, u points to your left.
* The image line is perpendicular to w, spans x in [-1, 1] along u, and lies at distance
  D = 1 / tan(fov_angle / 2) from e, so that its ends are seen at ±fov_angle/2.
* Pixel i of N (i = 0 … N-1) has its centre at x_i = -1 + (i + 0.5)·2/N, at the point
  p_i = e + x_i·u + D·w. Pixel 0 is at x = -1, the end of the line on your *right*; the scan
  lists pixels in that order (index i), and so do sweep images (column i).
* With n samples per pixel, sample k of pixel i sits at x = -1 + (i + (k + 0.5)/n)·2/N.
* The slides give a second pixel formula (from 2D to 3D), u_i = i·2/N_cols, i = 0, ±1, ±2, …,
  ±N_cols/2. raykit keeps it only to show it (:func:`slide_pixel_positions`): for even N_cols
  it lists N_cols + 1 positions, not N_cols, the outer two exactly on the ends of the image
  line (pixel edges, not centres), and it leaves no position at a pixel centre of x_i above
  (they fall half a pixel between them). Every camera in raykit uses x_i.
* Perspective rays start at e and go through p_i (direction p_i - e = x_i·u + D·w, unit
  length). Orthographic rays are parallel to w; their origins lie along an image line through e,
  ``width`` long: o_i = e + (width/2)·x_i·u (fov_angle plays no part).
* The letter D. The slides use D for two things: here, the distance from e to the image line;
  in the ray–sphere quadratic, the discriminant B² - 4AC (:mod:`raykit.spheres`). They never
  meet in one formula, so raykit keeps the slide's letter in both places and spells the other
  out where both could be meant: ``LineCamera.D`` is always this distance, and the sphere code
  calls its D ``discriminant``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from raykit.rays import normalize

PROJECTIONS = ("perspective", "orthographic")


@dataclass(frozen=True)
class LineCamera:
    """A line-scan camera (see the module conventions); points and vectors are ``(2,)``."""

    e: np.ndarray
    w: np.ndarray
    fov_angle: float
    pixels: int
    projection: str = "perspective"
    width: float = 2.0

    @cached_property
    def frame(self) -> tuple[np.ndarray, np.ndarray]:
        """(u, w): unit view direction w and u, w turned a quarter to the left; ``(2,)`` each."""
        w = normalize(np.asarray(self.w, dtype=float))
        return np.array([-w[1], w[0]]), w

    @property
    def D(self) -> float:  # noqa: N802 - the lecture's letter
        """Distance from e to the image line: 1 / tan(fov_angle / 2)."""
        return 1.0 / math.tan(math.radians(self.fov_angle) / 2.0)


def pixel_x(pixels: int, samples: int = 1) -> np.ndarray:
    """Image-line coordinates x of every sample, ``(pixels * samples,)``, pixel by pixel:
    x = -1 + (i + (k + 0.5)/n)·2/N, so n = 1 gives the pixel centres x_i."""
    # BEGIN SOLUTION
    # hint: x = -1 + (i + (k + 0.5)/n)·2/N for pixel i = 0..N-1 and sample k = 0..n-1, pixel by
    #       pixel
    i = np.repeat(np.arange(pixels), samples)
    k = np.tile(np.arange(samples), pixels)
    return -1.0 + (i + (k + 0.5) / samples) * (2.0 / pixels)
    # END SOLUTION


def slide_pixel_positions(n_cols: int) -> np.ndarray:
    """The slide's second formula as written, u_i = i·2/N_cols, i = 0, ±1, ±2, …, ±N_cols/2,
    in increasing order, ``(2·(N_cols // 2) + 1,)``: N_cols + 1 positions for even N_cols (from
    -1 to 1, both ends included), N_cols for odd (i up to ±(N_cols - 1)/2). Not used by any
    camera; compare :func:`pixel_x` (see the module conventions)."""
    i = np.arange(-(n_cols // 2), n_cols // 2 + 1)
    return i * (2.0 / n_cols)


def pixel_positions(camera: LineCamera, samples: int = 1) -> np.ndarray:
    """The points p_i = e + x_i·u + D·w on the image line, ``(pixels * samples, 2)``."""
    u, w = camera.frame
    x = pixel_x(camera.pixels, samples)
    return np.asarray(camera.e, float) + x[:, None] * u + camera.D * w


def line_rays(camera: LineCamera, samples: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """All rays of the camera: ``origins (M, 2)`` and unit ``directions (M, 2)``, with
    M = pixels·samples, in pixel order (the samples of pixel 0 first)."""
    # BEGIN SOLUTION
    # hint: perspective: origins e, directions normalize(x·u + D·w); orthographic: origins e +
    #       (width/2)·x·u, directions w
    u, w = camera.frame
    x = pixel_x(camera.pixels, samples)
    e = np.asarray(camera.e, float)
    if camera.projection == "orthographic":
        origins = e + (camera.width / 2.0) * x[:, None] * u
        directions = np.broadcast_to(w, origins.shape).copy()
    else:
        origins = np.broadcast_to(e, (len(x), 2)).copy()
        directions = normalize(x[:, None] * u + camera.D * w)  # p_i - e, no digits lost to e
    return origins, directions
    # END SOLUTION

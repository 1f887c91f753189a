"""Object order: the lecture's other loop, over objects first.

The slides contrast two ways to make an image. "Object-Ordered or Rasterization", as the slide
writes it::

    for each object {
        for each image pixel {
            if (object affects pixel)
            {
                do something
            }
        }
    }

and "Image-Ordered or Ray Tracing", the same two loops swapped::

    for each image pixel {
        for each object {
            if (object affects pixel)
            {
                do something
            }
        }
    }

:func:`raykit.render.render` is image order (made fast by tiles, :mod:`raykit.engine.tiles`).
This module is object order, :func:`render_object_order`, for the same 3D scenes: each object
in index order, over the pixels its screen rectangle covers (:mod:`raykit.engine.screen_bounds`,
conservative), where the ray through the pixel centre meets it (the renderer's own rays and
intersection functions) and, if that is nearer than the depth buffer's t, stores its index, t and
colour.

Ties are broken as the ray tracer breaks them (:mod:`raykit.scene`): an object replaces what a
pixel holds only when strictly nearer, and objects come in index order, so of two at the same t
the lower index stays. Cut-out texels are holes here as there. The result, for the pixel
centres, is the same ``object_index`` and ``t`` as the ray tracer's on every scene (tested on
the examples); the colour is each object's flat colour, unshaded (lights, shadows and mirrors
are the ray tracer's: they need rays from the hit points, which this loop does not cast).

A real rasteriser projects each object's shape and fills its pixels without any ray; this one
keeps the intersection test per (object, pixel) to give the very same image, so the two loops
differ only in their order and in what each pixel is tested against.
"""

from __future__ import annotations

import numpy as np

from raykit.billboards import Billboard, billboard_color_at, hit_billboard
from raykit.camera import rays_through
from raykit.engine.screen_bounds import object_bounds
from raykit.render import Render
from raykit.scene import Scene
from raykit.spheres import hit_sphere


def covered_pixels(
    bounds: tuple[float, float, float, float], width: int, height: int
) -> tuple[np.ndarray, np.ndarray]:
    """The pixels ``(rows (P,), cols (P,))`` whose centres lie in a screen rectangle
    (x0, x1, y0, y1) (continuous image coordinates, :mod:`raykit.camera`), row-major."""
    x0, x1, y0, y1 = bounds
    cols = np.arange(max(0, int(np.ceil(x0 - 0.5))), min(width, int(np.floor(x1 - 0.5)) + 1))
    rows = np.arange(max(0, int(np.ceil(y0 - 0.5))), min(height, int(np.floor(y1 - 0.5)) + 1))
    return np.repeat(rows, len(cols)), np.tile(cols, len(rows))


def render_object_order(scene: Scene) -> Render:
    """The scene drawn object by object into a depth buffer: ``object_index (H, W)`` (-1 for
    the background), depth ``t (H, W)`` (inf for none) and flat, unshaded ``rgb (H, W, 3)``,
    for the rays through the pixel centres (see the module docstring)."""
    camera = scene.camera
    height, width = camera.height, camera.width
    depth = np.full((height, width), np.inf)  # the depth buffer: t of what each pixel holds
    object_index = np.full((height, width), -1, dtype=np.int64)
    rgb = np.broadcast_to(np.asarray(scene.background, float), (height, width, 3)).copy()
    all_bounds = object_bounds(camera, scene.objects)
    for index, obj in enumerate(scene.objects):  # the slide's "for each object {"
        if np.isnan(all_bounds[index]).any():
            continue  # no pixel can see it
        rows, cols = covered_pixels(tuple(all_bounds[index]), width, height)
        if len(rows) == 0:
            continue
        # "for each image pixel {": only those it can affect, all at once, each with its ray
        origins, directions = rays_through(camera, cols + 0.5, rows + 0.5)
        if isinstance(obj, Billboard):
            t, alpha, beta = hit_billboard(origins, directions, obj)
        else:
            t = hit_sphere(origins, directions, obj.center, obj.radius)
        # "if (object affects pixel)": its ray meets it nearer than what the pixel holds
        nearer = np.flatnonzero(t < depth[rows, cols])  # strictly: ties keep the lower index
        if len(nearer) == 0:
            continue
        if isinstance(obj, Billboard):
            colors, opaque = billboard_color_at(obj, alpha, beta)(nearer)
            nearer, colors = nearer[opaque], colors[opaque]
        else:
            colors = obj.color
        r, c = rows[nearer], cols[nearer]
        depth[r, c] = t[nearer]  # the if's body, "do something": store its t, index and colour
        object_index[r, c] = index
        rgb[r, c] = colors
    return Render(rgb, object_index, depth)

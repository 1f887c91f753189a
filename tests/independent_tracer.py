"""An independent tracer of scene format v1, written from the spec text for the tests.

Scalar Python, one pixel at a time, sharing no code with raykit: the camera from the spec's
formulas, spheres by the geometric method (closest approach along the ray), billboards by
Cramer's rule on [a b -d]. Slow, so the tests use small images.
"""

from __future__ import annotations

import math

from PIL import Image


def _sub(p, q):
    return [p[0] - q[0], p[1] - q[1], p[2] - q[2]]


def _dot(p, q):
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]


def _cross(p, q):
    return [p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]]


def _unit(p):
    n = math.sqrt(_dot(p, p))
    return [p[0] / n, p[1] / n, p[2] / n]


def _sphere_t(o, d, center, radius):
    """Smallest t > 0 by closest approach: t_ca = (c - o)·d, h² = r² - |c - o - t_ca d|²."""
    co = _sub(center, o)
    t_ca = _dot(co, d)
    closest = [co[i] - t_ca * d[i] for i in range(3)]
    h2 = radius * radius - _dot(closest, closest)
    if h2 < 0:
        return None
    h = math.sqrt(h2)
    for t in (t_ca - h, t_ca + h):
        if t > 0:
            return t
    return None


def _billboard_hit(o, d, ul, a, b):
    """Solve o + t d = ul + alpha a + beta b by Cramer's rule; returns (t, alpha, beta)."""
    minus_d = [-d[0], -d[1], -d[2]]
    det = _dot(a, _cross(b, minus_d))
    if det == 0:
        return None
    r = _sub(o, ul)
    alpha = _dot(r, _cross(b, minus_d)) / det
    beta = _dot(a, _cross(r, minus_d)) / det
    t = _dot(a, _cross(b, r)) / det
    if t > 0 and 0 <= alpha <= 1 and 0 <= beta <= 1:
        return t, alpha, beta
    return None


def trace_object_index(scene: dict, folder) -> list[list[int]]:
    """Object index per pixel centre (spheres first, then billboards; -1 for none)."""
    cam = scene["camera"]
    eye, lookat, up = cam["eye"], cam["lookat"], cam["up"]
    width, height = cam["width"], cam["height"]
    w = _unit(_sub(eye, lookat))
    u = _unit(_cross(up, w))
    v = _cross(w, u)
    dist = math.sqrt(_dot(_sub(lookat, eye), _sub(lookat, eye)))
    plane_h = 2 * dist * math.tan(math.radians(cam["fov_angle"]) / 2)
    plane_w = plane_h * width / height
    ortho = cam.get("projection", "perspective") == "orthographic"

    textures = {}
    for bb in scene.get("billboards", []):
        if "image" in bb and bb["image"] not in textures:
            textures[bb["image"]] = Image.open(folder / bb["image"]).convert("RGBA")

    objects = [("sphere", s) for s in scene.get("spheres", [])]
    objects += [("billboard", b) for b in scene.get("billboards", [])]
    image = []
    for r in range(height):
        row = []
        for c in range(width):
            s = -plane_w / 2 + (c + 0.5) * plane_w / width
            t = plane_h / 2 - (r + 0.5) * plane_h / height
            in_plane = [s * u[i] + t * v[i] for i in range(3)]
            if ortho:
                o = [eye[i] + in_plane[i] for i in range(3)]
                d = [-w[0], -w[1], -w[2]]
            else:
                o = list(eye)
                d = _unit([in_plane[i] - dist * w[i] for i in range(3)])
            best_t, best = math.inf, -1
            for k, (kind, obj) in enumerate(objects):
                if kind == "sphere":
                    hit_t = _sphere_t(o, d, obj["center"], obj["radius"])
                else:
                    ul = obj["upper_left"]
                    hit = _billboard_hit(
                        o, d, ul, _sub(obj["upper_right"], ul), _sub(obj["lower_left"], ul)
                    )
                    hit_t = None
                    if hit is not None:
                        hit_t, alpha, beta = hit
                        if "image" in obj:
                            tex = textures[obj["image"]]
                            col = min(int(math.floor(alpha * tex.width)), tex.width - 1)
                            row_ = min(int(math.floor(beta * tex.height)), tex.height - 1)
                            if tex.getpixel((col, row_))[3] < 128:
                                hit_t = None
                if hit_t is not None and hit_t < best_t:
                    best_t, best = hit_t, k
            row.append(best)
        image.append(row)
    return image

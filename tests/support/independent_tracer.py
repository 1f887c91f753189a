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


class _Texture:
    """An image's texels as (colour in [0, 1], opaque); 16-bit grey scaled by 65535."""

    def __init__(self, path) -> None:
        image = Image.open(path)
        self.wide = image.mode.startswith("I")
        self.image = image if self.wide else image.convert("RGBA")
        self.width, self.height = image.size

    def texel(self, col, row):
        value = self.image.getpixel((col, row))
        if self.wide:
            grey = round(value * 255 / 65535) / 255
            return [grey] * 3, True
        return [value[0] / 255, value[1] / 255, value[2] / 255], value[3] >= 128


def _camera_rays(cam):
    """(row, column, o, d) of every pixel centre, from the spec's camera formulas."""
    eye, lookat, up = cam["eye"], cam["lookat"], cam["up"]
    width, height = cam["width"], cam["height"]
    w = _unit(_sub(eye, lookat))
    u = _unit(_cross(up, w))
    v = _cross(w, u)
    dist = math.sqrt(_dot(_sub(lookat, eye), _sub(lookat, eye)))
    plane_h = 2 * dist * math.tan(math.radians(cam["fov_angle"]) / 2)
    plane_w = plane_h * width / height
    ortho = cam.get("projection", "perspective") == "orthographic"
    for r in range(height):
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
            yield r, c, o, d


class _World:
    def __init__(self, scene: dict, folder) -> None:
        self.objects = [("sphere", s) for s in scene.get("spheres", [])]
        self.objects += [("billboard", b) for b in scene.get("billboards", [])]
        self.textures = {}
        for bb in scene.get("billboards", []):
            if "image" in bb and bb["image"] not in self.textures:
                self.textures[bb["image"]] = _Texture(folder / bb["image"])

    def nearest(self, o, d, skip=-1):
        """(t, object number, colour) of the nearest hit with t > 0, skipping object ``skip``;
        (inf, -1, None) for none."""
        best_t, best, best_color = math.inf, -1, None
        for k, (kind, obj) in enumerate(self.objects):
            if k == skip:
                continue
            color = obj.get("color")
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
                        tex = self.textures[obj["image"]]
                        col = min(int(math.floor(alpha * tex.width)), tex.width - 1)
                        row_ = min(int(math.floor(beta * tex.height)), tex.height - 1)
                        color, opaque = tex.texel(col, row_)
                        if not opaque:
                            hit_t = None
            if hit_t is not None and hit_t < best_t:
                best_t, best, best_color = hit_t, k, color
        return best_t, best, best_color


def trace_object_index(scene: dict, folder) -> list[list[int]]:
    """Object index per pixel centre (spheres first, then billboards; -1 for none)."""
    world = _World(scene, folder)
    cam = scene["camera"]
    image = [[-1] * cam["width"] for _ in range(cam["height"])]
    for r, c, o, d in _camera_rays(cam):
        image[r][c] = world.nearest(o, d)[1]
    return image


def trace_shaded(scene: dict, folder) -> tuple[list[list[int]], list[list[list[float]]]]:
    """Object index and colour per pixel centre of a lit scene, from FOCG 4.5-4.9's formulas.

    Written apart from raykit's shading: the normal of a billboard is flipped toward the ray by
    the sign of a determinant-free dot product, shadow and mirror rays skip the object they
    start on (a sphere or a flat billboard cannot be hit again by a ray leaving its lit side)
    instead of starting off the surface, and the recursion is plain recursion.
    """
    world = _World(scene, folder)
    cam = scene["camera"]
    background = scene.get("background", [0, 0, 0])
    ambient = scene.get("ambient", [0, 0, 0])
    lights = scene.get("lights", [])
    lit = "lights" in scene or "ambient" in scene
    shadows = scene.get("shadows", True) and len(world.objects) > 1
    depth_limit = scene.get("max_depth", 3)

    def radiance(o, d, depth, skip):
        t, k, color = world.nearest(o, d, skip)
        if k < 0:
            return k, list(background)
        kind, obj = world.objects[k]
        p = [o[i] + t * d[i] for i in range(3)]
        if kind == "sphere":
            n = [(p[i] - obj["center"][i]) / obj["radius"] for i in range(3)]
        else:
            ul = obj["upper_left"]
            n = _unit(_cross(_sub(obj["upper_right"], ul), _sub(obj["lower_left"], ul)))
            if _dot(n, d) > 0:
                n = [-x for x in n]
        if not lit:
            out = list(color)
        else:
            kd = obj.get("diffuse", color)
            ks = obj.get("specular", [0, 0, 0])
            shininess = obj.get("shininess", 32)
            out = [kd[i] * ambient[i] for i in range(3)]
            for light in lights:
                intensity = light.get("color", [1, 1, 1])
                if light["type"] == "directional":
                    l, far = _unit([-x for x in light["direction"]]), math.inf
                else:
                    to = _sub(light["position"], p)
                    l, far = _unit(to), math.sqrt(_dot(to, to))
                cos = _dot(n, l)
                if cos <= 0:
                    continue
                if shadows and world.nearest(p, l, skip=k)[0] < far:
                    continue
                h = _unit([l[i] - d[i] for i in range(3)])
                spec = max(0.0, _dot(n, h)) ** shininess
                for i in range(3):
                    out[i] += kd[i] * intensity[i] * cos + ks[i] * intensity[i] * spec
        km = obj.get("mirror", [0, 0, 0])
        if depth < depth_limit and any(x > 0 for x in km):
            dn = _dot(d, n)
            r = [d[i] - 2 * dn * n[i] for i in range(3)]
            reflected = radiance(p, r, depth + 1, k)[1]
            out = [out[i] + km[i] * reflected[i] for i in range(3)]
        return k, out

    index = [[-1] * cam["width"] for _ in range(cam["height"])]
    rgb = [[None] * cam["width"] for _ in range(cam["height"])]
    for r, c, o, d in _camera_rays(cam):
        index[r][c], rgb[r][c] = radiance(o, d, 0, -1)
    return index, rgb

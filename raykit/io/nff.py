"""Scenes in NFF, the format of Eric Haines' Standard Procedural Databases (SPD).

What is read (one entity per line, ``#`` starts a comment):

* ``v`` and the view block after it: ``from``, ``at``, ``up``, ``angle``, ``hither``,
  ``resolution``. NFF's ``angle`` is measured between the centres of the outermost pixels,
  raykit's ``fov_angle`` between the outer edges of the image, so for yres rows
  tan(fov_angle/2) = tan(angle/2) · yres / (yres - 1). The angle is taken as the vertical one
  (SPD images are square, where the two agree). ``hither`` is ignored: a hit counts for t > 0.
* ``b r g b``: the background.
* ``f r g b Kd Ks Shine T ior``: the surface of the objects that follow: colour r g b, diffuse
  reflectance kd = Kd·(r, g, b), a white highlight ks = Ks with exponent p = Shine, and, as in
  Whitted's ray tracer that NFF was written for, a white mirror reflectance km = Ks. T and ior
  (transmission, refraction) are ignored: raykit has no refraction. With only r g b given,
  Kd = 1 and Ks = 0.
* ``s x y z r``: a sphere.
* ``p n`` or ``pp n`` and n vertex lines (``pp`` lines also carry a normal, ignored): a polygon,
  read as a billboard when it is a parallelogram (v0 + v2 = v1 + v3), v0 its upper_left, v1
  upper_right, v3 lower_left.
* ``l x y z [r g b]``: a point light (:mod:`raykit.lights`), white when no colour is given.
  A file with lights is rendered lit, with shadows (:mod:`raykit.shading`); one without shows
  flat colours.

Anything else (cones and cylinders ``c``, other polygons, unknown entities) is a one-line
:class:`raykit.io.errors.SceneError` naming the file and the line.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from raykit.io.errors import SceneError
from raykit.io.scene_json import scene_from_dict
from raykit.scene import Scene

VIEW_KEYS = ("from", "at", "up", "angle", "hither", "resolution")


def load_nff(path: str | Path) -> Scene:
    """Read an NFF file as a scene; raises :class:`raykit.io.errors.SceneError`."""
    source = str(path)
    try:
        lines = Path(path).read_text(encoding="utf-8", errors="replace").splitlines()
    except FileNotFoundError:
        raise SceneError(source, "", "scene file not found") from None
    except OSError as exc:
        raise SceneError(source, "", f"scene file cannot be read ({exc.strerror})") from None
    return scene_from_nff(lines, source)


def _numbers(words: list[str], count: int, source: str, number: int, entity: str) -> list[float]:
    try:
        values = [float(w) for w in words[:count]]
    except ValueError:
        values = []
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise SceneError(source, f"line {number}", f"expected {count} numbers after {entity!r}")
    return values


def scene_from_nff(lines: list[str], source: str = "<nff>") -> Scene:
    """Read NFF ``lines`` (see the module docstring) into a validated scene."""
    view: dict[str, list[float]] = {}
    background = [0.0, 0.0, 0.0]
    surface: dict = {"color": [1.0, 1.0, 1.0]}
    spheres, billboards, lights = [], [], []
    numbered = [(i + 1, line.split("#", 1)[0].split()) for i, line in enumerate(lines)]
    numbered = [(n, words) for n, words in numbered if words]
    k = 0
    while k < len(numbered):
        number, words = numbered[k]
        k += 1
        entity, rest = words[0], words[1:]
        if entity == "v":
            continue
        if entity in VIEW_KEYS:
            count = {"angle": 1, "hither": 1, "resolution": 2}.get(entity, 3)
            view[entity] = _numbers(rest, count, source, number, entity)
        elif entity == "b":
            background = [min(max(c, 0.0), 1.0) for c in _numbers(rest, 3, source, number, entity)]
        elif entity == "f":
            surface = _surface(_numbers(rest, max(3, min(len(rest), 6)), source, number, entity))
        elif entity == "l":
            values = _numbers(rest, 6 if len(rest) >= 6 else 3, source, number, entity)
            light = {"type": "point", "position": values[:3]}
            if len(values) == 6:
                light["color"] = [max(c, 0.0) for c in values[3:]]
            lights.append(light)
        elif entity == "s":
            x, y, z, r = _numbers(rest, 4, source, number, entity)
            spheres.append({"center": [x, y, z], "radius": r, **surface})
        elif entity in ("p", "pp"):
            (count,) = _numbers(rest, 1, source, number, entity)
            vertices = []
            for _ in range(int(count)):
                if k == len(numbered):
                    raise SceneError(source, f"line {number}", "the polygon's vertices end early")
                vertex_number, vertex = numbered[k]
                k += 1
                vertices.append(_numbers(vertex, 3, source, vertex_number, "a vertex"))
            billboards.append({**_parallelogram(vertices, source, number), **surface})
        else:
            what = {"c": "cones and cylinders"}.get(entity, f"the entity {entity!r}")
            raise SceneError(source, f"line {number}", f"{what}: not supported by raykit")
    missing = [key for key in ("from", "at", "up", "angle", "resolution") if key not in view]
    if missing:
        raise SceneError(source, "view", f"missing {', '.join(missing)}")
    width, height = (int(v) for v in view["resolution"])
    half = math.radians(view["angle"][0]) / 2
    rows = max(height, 2)
    fov_angle = math.degrees(2 * math.atan(math.tan(half) * rows / (rows - 1)))
    camera = {
        "eye": view["from"],
        "lookat": view["at"],
        "up": view["up"],
        "fov_angle": fov_angle,
        "width": width,
        "height": height,
    }
    data = {
        "camera": camera,
        "background": background,
        "spheres": spheres,
        "billboards": billboards,
    }
    if lights:
        data["lights"] = lights
    return scene_from_dict(data, source=source)


def _surface(values: list[float]) -> dict:
    """Scene fields of an ``f`` line's r g b [Kd Ks Shine]."""
    color = [min(max(c, 0.0), 1.0) for c in values[:3]]
    if len(values) < 6:
        return {"color": color}
    kd, ks, shine = values[3:6]
    kd, ks = min(max(kd, 0.0), 1.0), min(max(ks, 0.0), 1.0)
    fields = {"color": color, "diffuse": [kd * c for c in color]}
    if ks > 0:
        fields.update(specular=[ks] * 3, shininess=max(shine, 1e-3), mirror=[ks] * 3)
    return fields


def _parallelogram(vertices: list[list[float]], source: str, number: int) -> dict:
    v = np.array(vertices)
    if len(v) != 4 or not np.allclose(v[0] + v[2], v[1] + v[3], atol=1e-9 * (1 + np.abs(v).max())):
        raise SceneError(
            source,
            f"line {number}",
            f"a polygon of {len(v)} vertices that is not a parallelogram: raykit "
            "renders billboards, which are parallelograms",
        )
    return {
        "upper_left": v[0].tolist(),
        "upper_right": v[1].tolist(),
        "lower_left": v[3].tolist(),
    }

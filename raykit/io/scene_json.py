"""Scene files, format v1 (JSON), read into :class:`raykit.scene.Scene`.

The format is documented in ``docs/scene-format.md`` and published as a JSON Schema in
``raykit/io/schemas/scene-v1.schema.json``. Every field is checked as it is read
(:mod:`raykit.io.fields`); a bad one is a :class:`raykit.io.errors.SceneError` naming the file
and the field, before any rendering starts.
"""

from __future__ import annotations

import operator
from collections.abc import Sequence
from itertools import chain, repeat
from pathlib import Path
from typing import Any

import numpy as np

from raykit.billboards import Billboard, is_degenerate
from raykit.camera import PROJECTIONS, Camera, DegenerateFrameError, camera_frame
from raykit.io.fields import Field, read_json_file, refuse_other_format
from raykit.io.textures import Texture
from raykit.lights import LIGHT_TYPES, DirectionalLight, Light, PointLight
from raykit.materials import DEFAULT_SHININESS, PLAIN, Material
from raykit.scene import DEFAULT_MAX_DEPTH, Scene
from raykit.spheres import Sphere, SphereTable

MAX_IMAGE_SIDE = 16384
MAX_DEPTH_LIMIT = 16
MATERIAL_FIELDS = ("diffuse", "specular", "shininess", "mirror")


def load_scene(path: str | Path) -> Scene:
    """Read and validate a v1 scene file; raises :class:`raykit.io.errors.SceneError`."""
    data, source = read_json_file(path)
    return scene_from_dict(data, source=source, folder=Path(path).parent)


def scene_from_dict(data: Any, source: str = "<scene>", folder: str | Path = ".") -> Scene:
    """Validate parsed JSON ``data`` as a v1 scene; texture paths are relative to ``folder``."""
    refuse_other_format(data, source, "3d")
    top = Field(data, source).object(
        required=("camera",),
        optional=(
            "$schema",
            "background",
            "spheres",
            "billboards",
            "lights",
            "ambient",
            "shadows",
            "max_depth",
        ),
    )
    camera = _read_camera(top["camera"])
    background = top["background"].color() if "background" in top else np.zeros(3)
    spheres = _read_spheres(top["spheres"]) if "spheres" in top else ()
    textures: dict[Path, Texture] = {}  # one per file, however many billboards name it
    billboards = (
        tuple(_read_billboard(f, Path(folder), textures) for f in top["billboards"].items())
        if "billboards" in top
        else ()
    )
    return Scene(
        camera,
        spheres,
        billboards,
        background,
        source,
        lights=tuple(_read_light(f) for f in top["lights"].items()) if "lights" in top else (),
        ambient=top["ambient"].intensity() if "ambient" in top else None,
        shadows=top["shadows"].boolean() if "shadows" in top else True,
        max_depth=(
            top["max_depth"].integer(ge=0, le=MAX_DEPTH_LIMIT)
            if "max_depth" in top
            else DEFAULT_MAX_DEPTH
        ),
    )


def _read_light(node: Field) -> Light:
    kind = node.object(required=("type",), optional=("direction", "position", "color", "name"))
    light_type = kind["type"].string(LIGHT_TYPES)
    place, other = ("direction", "position")
    if light_type == "point":
        place, other = other, place
    if other in kind:
        raise kind[other].error(f'a {light_type} light takes "{place}", not "{other}"')
    f = node.object(required=("type", place), optional=("color", "name"))
    color = f["color"].intensity() if "color" in f else np.ones(3)
    if light_type == "point":
        return PointLight(f["position"].vector(3), color)
    direction = f["direction"].vector(3)
    if not np.any(direction):
        raise f["direction"].error("is the zero vector, so the light shines nowhere")
    return DirectionalLight(direction, color)


def _read_material(f: dict[str, Field]) -> Material:
    if not any(key in f for key in MATERIAL_FIELDS):
        return PLAIN
    return Material(
        diffuse=f["diffuse"].color() if "diffuse" in f else None,
        specular=f["specular"].color() if "specular" in f else np.zeros(3),
        shininess=f["shininess"].number(gt=0) if "shininess" in f else DEFAULT_SHININESS,
        mirror=f["mirror"].color() if "mirror" in f else np.zeros(3),
    )


def _read_camera(node: Field) -> Camera:
    f = node.object(
        required=("eye", "lookat", "up", "fov_angle", "width", "height"),
        optional=("projection",),
    )
    eye, lookat, up = (f[key].vector(3) for key in ("eye", "lookat", "up"))
    fov_angle = f["fov_angle"].number(gt=0, lt=180)
    width = f["width"].integer(ge=1, le=MAX_IMAGE_SIDE)
    height = f["height"].integer(ge=1, le=MAX_IMAGE_SIDE)
    projection = f["projection"].string(PROJECTIONS) if "projection" in f else "perspective"
    try:
        camera_frame(eye, lookat, up)
    except DegenerateFrameError as exc:
        raise f[exc.culprit].error(str(exc)) from None
    return Camera(eye, lookat, up, fov_angle, width, height, projection)


def _read_spheres(node: Field) -> Sequence[Sphere]:
    """All spheres: plain ones in bulk (:func:`_plain_spheres`), else field by field."""
    plain = _plain_spheres(node.value)
    if plain is not None:
        return plain
    return tuple(_read_sphere(f) for f in node.items())


PLAIN_SPHERE_KEYS = {"center", "radius", "color"}


def _plain_spheres(values) -> SphereTable | None:
    """Spheres of only center, radius and color, every value valid, checked all at once (a scene
    of 600,000 spheres loads in well under a second) and kept as a
    :class:`raykit.spheres.SphereTable`; None when any sphere is not that plain or not valid,
    and then the field-by-field reading finds and names the problem."""
    if not isinstance(values, list) or not values:
        return None
    try:
        if not all(map(operator.eq, map(dict.keys, values), repeat(PLAIN_SPHERE_KEYS))):
            return None
        centers = [v["center"] for v in values]
        radii = [v["radius"] for v in values]
        colors = [v["color"] for v in values]
        numbers = chain(chain.from_iterable(centers), radii, chain.from_iterable(colors))
        if not set(map(type, numbers)) <= {int, float}:  # no bool, string, list or None
            return None
        columns = [np.array(x, dtype=float) for x in (centers, radii, colors)]
    except (TypeError, ValueError, OverflowError):  # a non-dict, non-list, or ragged rows
        return None
    center, radius, color = columns
    if center.shape != (len(values), 3) or color.shape != (len(values), 3):
        return None
    valid = (
        all(np.isfinite(c).all() for c in columns)
        and (radius > 0).all()
        and ((color >= 0) & (color <= 1)).all()
    )
    return SphereTable(center, radius, color) if valid else None


def _read_sphere(node: Field) -> Sphere:
    f = node.object(required=("center", "radius", "color"), optional=("name", *MATERIAL_FIELDS))
    return Sphere(
        center=f["center"].vector(3),
        radius=f["radius"].number(gt=0),
        color=f["color"].color(),
        name=f["name"].string() if "name" in f else None,
        material=_read_material(f),
    )


def _read_billboard(node: Field, folder: Path, textures: dict[Path, Texture]) -> Billboard:
    f = node.object(
        required=("upper_left", "lower_left", "upper_right"),
        optional=("image", "color", "name", *MATERIAL_FIELDS),
    )
    upper_left, lower_left, upper_right = (
        f[key].vector(3) for key in ("upper_left", "lower_left", "upper_right")
    )
    for corner, other in (("upper_right", upper_right), ("lower_left", lower_left)):
        if np.array_equal(other, upper_left):
            raise f[corner].error("coincides with upper_left, so the billboard has no area")
    if is_degenerate(upper_right - upper_left, lower_left - upper_left):
        raise node.error("corners upper_left, lower_left and upper_right are collinear")
    node.exactly_one_of(f, "image", "color")
    color = f["color"].color() if "color" in f else None
    texture = None
    if "image" in f:
        if "diffuse" in f:
            raise f["diffuse"].error(
                'a billboard with an "image" takes its diffuse colour from the image'
            )
        path = folder / f["image"].string()
        texture = textures.get(path.resolve())
        if texture is None:
            texture = textures[path.resolve()] = Texture(path, f["image"].source, f["image"].path)
    name = f["name"].string() if "name" in f else None
    return Billboard(
        upper_left, lower_left, upper_right, color, texture, name, material=_read_material(f)
    )

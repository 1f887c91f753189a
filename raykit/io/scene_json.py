"""Scene files, formats v1 and v2 (JSON), read into :class:`raykit.scene.Scene`.

The format is documented in ``docs/scene-format.md`` and published as JSON Schemas in
``raykit/io/schemas/scene-v1.schema.json`` and ``scene-v2.schema.json``. Every field is checked
as it is read (:mod:`raykit.io.fields`); a bad one is a :class:`raykit.io.errors.SceneError`
naming the file and the field, before any rendering starts.

Format v2 (stage 5, distributed ray tracing) is v1 with ``"version": 2`` at the top, and adds
area lights (FOCG's, of a ``color``, or physically based, of a ``radiance``), the camera's
``aperture`` and ``focus_distance``, a mirror's ``glossiness``, and a ``render`` object
(``samples_per_pixel``, ``sampler``, ``seed``, ``shutter``). A file without ``version`` is v1,
read as it always was; a v2 field in it is refused, naming the field and the fix. A scene with a
``shutter`` moves its spheres by their ``velocity`` (motion blur); a billboard's velocity is
refused there.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Sequence
from itertools import chain, repeat
from pathlib import Path
from typing import Any

import numpy as np

from raykit.billboards import Billboard, is_degenerate
from raykit.camera import PROJECTIONS, Camera, DegenerateFrameError
from raykit.io.fields import Field, read_scene_file, top_fields
from raykit.io.textures import Texture
from raykit.lights import LIGHT_TYPES, AreaLight, DirectionalLight, Light, PointLight
from raykit.materials import DEFAULT_SHININESS, PLAIN, Material
from raykit.sampling import SAMPLERS, Sampling
from raykit.scene import DEFAULT_MAX_DEPTH, Scene
from raykit.spheres import Sphere, SphereTable

MAX_IMAGE_SIDE = 16384
MAX_DEPTH_LIMIT = 16
MATERIAL_FIELDS = ("diffuse", "specular", "shininess", "mirror", "glossiness")
VERSION = 2  # the newest format; a file without "version" is v1
MAX_SAMPLES_PER_PIXEL = 4096
MAX_SEED = 2**32 - 1


def load_scene(path: str | Path) -> Scene:
    """Read and validate a v1 or v2 scene file; raises :class:`raykit.io.errors.SceneError`."""
    return read_scene_file(path, scene_from_dict)


def scene_from_dict(data: Any, source: str = "<scene>", folder: str | Path = ".") -> Scene:
    """Validate parsed JSON ``data`` as a v1 or v2 scene; texture paths are relative to
    ``folder``."""
    top = top_fields(
        data,
        source,
        "3d",
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
            "version",
            "render",
        ),
    )
    v2 = _read_version(top)
    camera = _read_camera(top["camera"], v2)
    background = top["background"].color() if "background" in top else np.zeros(3)
    spheres = _read_spheres(top["spheres"], v2) if "spheres" in top else ()
    textures: dict[Path, Texture] = {}  # one per file, however many billboards name it
    billboards = (
        tuple(_read_billboard(f, Path(folder), textures, v2) for f in top["billboards"].items())
        if "billboards" in top
        else ()
    )
    sampling = _read_sampling(top["render"], v2) if "render" in top else Sampling()
    if sampling.shutter is not None:
        _refuse_moving_billboards(top)
    return Scene(
        camera,
        spheres,
        billboards,
        background,
        source,
        velocities=_read_velocities(top, spheres),
        lights=tuple(_read_light(f, v2) for f in top["lights"].items()) if "lights" in top else (),
        ambient=top["ambient"].intensity() if "ambient" in top else None,
        shadows=top["shadows"].boolean() if "shadows" in top else True,
        max_depth=(
            top["max_depth"].integer(ge=0, le=MAX_DEPTH_LIMIT)
            if "max_depth" in top
            else DEFAULT_MAX_DEPTH
        ),
        sampling=sampling,
    )


def _read_velocities(top: dict[str, Field], spheres: Sequence[Sphere]) -> np.ndarray | None:
    """Every object's ``velocity`` ``(K, 3)`` in object index order (zero where it has none), or
    None when no object has one. The objects' other fields are read by their own readers;
    ``spheres`` as :func:`_read_spheres` read them (plain spheres, a
    :class:`~raykit.spheres.SphereTable`, have no velocity)."""
    # the plain values first, and only where a velocity may be: a Field for each of 600,000
    # still spheres took seconds
    kinds = ("billboards",) if isinstance(spheres, SphereTable) else ("spheres", "billboards")
    values = (v for key in kinds if key in top for v in top[key].value)
    if not any(isinstance(v, dict) and "velocity" in v for v in values):
        return None
    objects = [f for key in ("spheres", "billboards") if key in top for f in top[key].items()]
    moving = [isinstance(f.value, dict) and "velocity" in f.value for f in objects]
    return np.array(
        [
            Field(f.value["velocity"], f.source, f"{f.path}.velocity").vector(3)
            if move
            else np.zeros(3)
            for f, move in zip(objects, moving, strict=True)
        ]
    )


def _refuse_moving_billboards(top: dict[str, Field]) -> None:
    """Only spheres move in a render with a shutter: a billboard's velocity is refused there."""
    for f in top["billboards"].items() if "billboards" in top else ():
        if isinstance(f.value, dict) and "velocity" in f.value:
            velocity = Field(f.value["velocity"], f.source, f"{f.path}.velocity")
            raise velocity.error(
                "only spheres move during the shutter (motion blur); remove the billboard's "
                'velocity or the render\'s "shutter"'
            )


def _read_version(top: dict[str, Field]) -> bool:
    """Whether the scene is format v2 (``"version": 2``); without ``version`` it is v1."""
    if "version" not in top:
        return False
    f = top["version"]
    if f.integer() != VERSION:
        raise f.error(f'must be {VERSION}; a scene without "version" is format v1')
    return True


def _needs_v2(f: Field, v2: bool, what: str) -> None:
    """Refuse a v2 field (``what`` it is) in a v1 scene, saying how to make it v2."""
    if not v2:
        raise f.error(f'{what} scene format v2: add "version": {VERSION} at the top')


def _read_sampling(node: Field, v2: bool) -> Sampling:
    _needs_v2(node, v2, "render settings are")
    f = node.object(required=(), optional=("samples_per_pixel", "sampler", "seed", "shutter"))
    count = (
        f["samples_per_pixel"].integer(ge=1, le=MAX_SAMPLES_PER_PIXEL)
        if "samples_per_pixel" in f
        else 1
    )
    sampler = f["sampler"].string(SAMPLERS) if "sampler" in f else Sampling.sampler
    seed = f["seed"].integer(ge=0, le=MAX_SEED) if "seed" in f else 0
    where = f["samples_per_pixel"] if "samples_per_pixel" in f else node
    if sampler == "jittered" and math.isqrt(count) ** 2 != count:
        raise where.error(f'the "jittered" sampler takes n x n samples (a square), got {count}')
    if sampler == "sobol" and count & (count - 1):
        raise where.error(f'the "sobol" sampler takes a power of two samples, got {count}')
    shutter = _read_shutter(f["shutter"]) if "shutter" in f else None
    return Sampling(count, sampler, seed, shutter)


def _read_shutter(f: Field) -> tuple[float, float]:
    """The shutter interval [T0, T1], 0 <= T0 <= T1 (T1 = T0: every ray at T0)."""
    shutter_open, shutter_close = f.vector(2, ge=0.0)
    if shutter_close < shutter_open:
        raise f.error(
            f"closes before it opens: [open, close] must have open <= close, got "
            f"[{shutter_open:g}, {shutter_close:g}]"
        )
    return (shutter_open, shutter_close)


def _read_area_light(node: Field) -> AreaLight:
    f = node.object(
        required=("type", "corner", "edge1", "edge2"), optional=("color", "radiance", "name")
    )
    corner, edge1, edge2 = (f[key].vector(3) for key in ("corner", "edge1", "edge2"))
    for key, edge in (("edge1", edge1), ("edge2", edge2)):
        if not np.any(edge):
            raise f[key].error("is the zero vector, so the light has no area")
    if is_degenerate(edge1, edge2):
        raise f["edge1"].error("must not be parallel to edge2, or the light has no area")
    if "radiance" in f:  # the physically based light (raykit.lights.area_intensity)
        if "color" in f:
            raise f["radiance"].error(
                "is the physically based light's radiance L, \"color\" FOCG's intensity I: "
                "give one of them"
            )
        return AreaLight(corner, edge1, edge2, f["radiance"].intensity(), physical=True)
    color = f["color"].intensity() if "color" in f else np.ones(3)
    return AreaLight(corner, edge1, edge2, color)


LIGHT_FIELDS = ("direction", "position", "color", "radiance", "name", "corner", "edge1", "edge2")


def _read_light(node: Field, v2: bool = False) -> Light:
    kind = node.object(
        required=("type",),
        optional=LIGHT_FIELDS,
    )
    light_type = kind["type"].string(LIGHT_TYPES)
    if light_type == "area":
        _needs_v2(kind["type"], v2, '"area" lights are')
        return _read_area_light(node)
    place, other = ("direction", "position")
    if light_type == "point":
        place, other = other, place
    if other in kind:
        raise kind[other].error(f'a {light_type} light takes "{place}", not "{other}"')
    if "radiance" in kind:
        raise kind["radiance"].error(f'is an area light\'s: a {light_type} light takes "color"')
    f = node.object(required=("type", place), optional=("color", "name"))
    color = f["color"].intensity() if "color" in f else np.ones(3)
    if light_type == "point":
        return PointLight(f["position"].vector(3), color)
    direction = f["direction"].vector(3)
    if not np.any(direction):
        raise f["direction"].error("is the zero vector, so the light shines nowhere")
    return DirectionalLight(direction, color)


def _read_material(f: dict[str, Field], v2: bool = False) -> Material:
    if not any(key in f for key in MATERIAL_FIELDS):
        return PLAIN
    mirror = f["mirror"].color() if "mirror" in f else np.zeros(3)
    glossiness = 0.0
    if "glossiness" in f:
        _needs_v2(f["glossiness"], v2, "glossy mirrors are")
        glossiness = f["glossiness"].number(ge=0)
        if glossiness > 0 and not mirror.any():
            raise f["glossiness"].error(
                'blurs a mirror\'s reflection: give the object a "mirror" (km) too'
            )
    return Material(
        diffuse=f["diffuse"].color() if "diffuse" in f else None,
        specular=f["specular"].color() if "specular" in f else np.zeros(3),
        shininess=f["shininess"].number(gt=0) if "shininess" in f else DEFAULT_SHININESS,
        mirror=mirror,
        glossiness=glossiness,
    )


def _read_camera(node: Field, v2: bool = False) -> Camera:
    f = node.object(
        required=("eye", "lookat", "up", "fov_angle", "width", "height"),
        optional=("projection", "aperture", "focus_distance"),
    )
    for key in ("aperture", "focus_distance"):
        if key in f:
            _needs_v2(f[key], v2, "the thin lens is")
    aperture = f["aperture"].number(ge=0) if "aperture" in f else 0.0
    focus_distance = f["focus_distance"].number(gt=0) if "focus_distance" in f else None
    eye, lookat, up = (f[key].vector(3) for key in ("eye", "lookat", "up"))
    fov_angle = f["fov_angle"].number(gt=0, lt=180)
    width = f["width"].integer(ge=1, le=MAX_IMAGE_SIDE)
    height = f["height"].integer(ge=1, le=MAX_IMAGE_SIDE)
    projection = f["projection"].string(PROJECTIONS) if "projection" in f else "perspective"
    if aperture > 0 and projection == "orthographic":
        raise f["aperture"].error("an orthographic camera has no lens: its rays are parallel")
    camera = Camera(eye, lookat, up, fov_angle, width, height, projection, aperture, focus_distance)
    try:
        camera.frame  # noqa: B018 (made once, here, and kept for every ray the camera makes)
    except DegenerateFrameError as exc:
        raise f[exc.culprit].error(str(exc)) from None
    return camera


def _read_spheres(node: Field, v2: bool = False) -> Sequence[Sphere]:
    """All spheres: plain ones in bulk (:func:`_plain_spheres`), else field by field."""
    plain = _plain_spheres(node.value)
    if plain is not None:
        return plain
    return tuple(_read_sphere(f, v2) for f in node.items())


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
        if set(map(len, centers)) != {3} or set(map(len, colors)) != {3}:
            return None
        # flat lists: numpy makes an array of one far faster than of a list of lists
        centers, colors = list(chain.from_iterable(centers)), list(chain.from_iterable(colors))
        if not set(map(type, chain(centers, radii, colors))) <= {int, float}:
            return None  # a bool, string, list, object or None, even where a list's length is 3
        columns = [np.array(x, dtype=float) for x in (centers, radii, colors)]
    except (TypeError, ValueError, OverflowError):  # a non-dict, a number for a list, 10**400
        return None
    center, radius, color = columns[0].reshape(-1, 3), columns[1], columns[2].reshape(-1, 3)
    valid = (
        all(np.isfinite(c).all() for c in columns)
        and (radius > 0).all()
        and ((color >= 0) & (color <= 1)).all()
    )
    return SphereTable(center, radius, color) if valid else None


def _read_sphere(node: Field, v2: bool = False) -> Sphere:
    f = node.object(
        required=("center", "radius", "color"),
        optional=("name", "velocity", *MATERIAL_FIELDS),
    )
    return Sphere(
        center=f["center"].vector(3),
        radius=f["radius"].number(gt=0),
        color=f["color"].color(),
        name=f["name"].string() if "name" in f else None,
        material=_read_material(f, v2),
    )


def _read_billboard(
    node: Field, folder: Path, textures: dict[Path, Texture], v2: bool = False
) -> Billboard:
    f = node.object(
        required=("upper_left", "lower_left", "upper_right"),
        optional=("image", "color", "name", "velocity", *MATERIAL_FIELDS),
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
        texture = textures.get(same := path.resolve())
        if texture is None:
            texture = textures[same] = Texture(path, f["image"].source, f["image"].path)
    name = f["name"].string() if "name" in f else None
    return Billboard(
        upper_left, lower_left, upper_right, color, texture, name, material=_read_material(f, v2)
    )

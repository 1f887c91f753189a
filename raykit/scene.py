"""A scene: a camera, a background colour, spheres and billboards; read from JSON (format v1).

The format is documented in ``docs/scene-format.md`` and published as a JSON Schema in
``raykit/schemas/scene-v1.schema.json``. Geometry conventions live with the objects:
:mod:`raykit.camera`, :mod:`raykit.spheres`, :mod:`raykit.billboards`.

Object indices. Wherever raykit reports "which object a ray hit" (the renderer's
``object_index`` image, diagrams, grading), object i counts the spheres first, in file order,
then the billboards: spheres are 0 .. S-1, billboards S .. S+B-1, and -1 is "nothing". The same
order breaks ties: of two objects hit at exactly the same t, the lower index wins.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from raykit.billboards import Billboard, is_degenerate
from raykit.camera import PROJECTIONS, Camera, DegenerateFrameError, camera_frame
from raykit.fields import Field, read_json_file
from raykit.spheres import Sphere
from raykit.textures import Texture

MAX_IMAGE_SIDE = 16384


@dataclass(frozen=True)
class Scene:
    """Everything the renderer needs; ``source`` names where it came from, for messages."""

    camera: Camera
    spheres: tuple[Sphere, ...] = ()
    billboards: tuple[Billboard, ...] = ()
    background: np.ndarray = field(default_factory=lambda: np.zeros(3))
    source: str = "<scene>"

    @property
    def objects(self) -> tuple[Sphere | Billboard, ...]:
        """All objects in index order (spheres, then billboards); see the module docstring."""
        return self.spheres + self.billboards


def load_scene(path: str | Path) -> Scene:
    """Read and validate a v1 scene file; raises :class:`raykit.errors.SceneError`."""
    data, source = read_json_file(path)
    return scene_from_dict(data, source=source, folder=Path(path).parent)


def scene_from_dict(data: Any, source: str = "<scene>", folder: str | Path = ".") -> Scene:
    """Validate parsed JSON ``data`` as a v1 scene; texture paths are relative to ``folder``."""
    top = Field(data, source).object(
        required=("camera",), optional=("$schema", "background", "spheres", "billboards")
    )
    camera = _read_camera(top["camera"])
    background = top["background"].color() if "background" in top else np.zeros(3)
    spheres = tuple(_read_sphere(f) for f in top["spheres"].items()) if "spheres" in top else ()
    billboards = (
        tuple(_read_billboard(f, Path(folder)) for f in top["billboards"].items())
        if "billboards" in top
        else ()
    )
    return Scene(camera, spheres, billboards, background, source)


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


def _read_sphere(node: Field) -> Sphere:
    f = node.object(required=("center", "radius", "color"), optional=("name",))
    return Sphere(
        center=f["center"].vector(3),
        radius=f["radius"].number(gt=0),
        color=f["color"].color(),
        name=f["name"].string() if "name" in f else None,
    )


def _read_billboard(node: Field, folder: Path) -> Billboard:
    f = node.object(
        required=("upper_left", "lower_left", "upper_right"), optional=("image", "color", "name")
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
        texture = Texture(folder / f["image"].string(), f["image"].source, f["image"].path)
    name = f["name"].string() if "name" in f else None
    return Billboard(upper_left, lower_left, upper_right, color, texture, name)

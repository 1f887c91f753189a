"""Line-scan scene files (JSON), read into :class:`raykit.linescan.scene.LineScene`.

The format is documented in ``docs/linescan-format.md`` and published as a JSON Schema in
``raykit/io/schemas/linescan-v1.schema.json``; it is read with the same field checks and
one-line errors as the 3D format (:mod:`raykit.io.fields`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from raykit.io.fields import Field, read_scene_file, top_fields
from raykit.io.textures import Texture
from raykit.linescan.camera import PROJECTIONS, LineCamera
from raykit.linescan.objects import Ball, Billboard
from raykit.linescan.scene import DEFAULT_SCANS, LineScene

MAX_PIXELS = 16384
MAX_SCANS = 16384


def load_line_scene(path: str | Path) -> LineScene:
    """Read and validate a line-scan scene file; raises :class:`raykit.io.errors.SceneError`."""
    return read_scene_file(path, line_scene_from_dict)


def line_scene_from_dict(data: Any, source: str = "<scene>", folder: str | Path = ".") -> LineScene:
    """Validate parsed JSON ``data`` as a line-scan scene; image paths are relative to
    ``folder``."""
    top = top_fields(
        data,
        source,
        "linescan",
        required=("camera",),
        optional=("$schema", "background", "balls", "billboards", "scans"),
    )
    camera, camera_velocity = _read_camera(top["camera"])
    return LineScene(
        camera=camera,
        balls=tuple(_read_ball(f) for f in top["balls"].items()) if "balls" in top else (),
        billboards=(
            tuple(_read_billboard(f, Path(folder)) for f in top["billboards"].items())
            if "billboards" in top
            else ()
        ),
        background=top["background"].color() if "background" in top else np.zeros(3),
        camera_velocity=camera_velocity,
        scans=top["scans"].integer(ge=1, le=MAX_SCANS) if "scans" in top else DEFAULT_SCANS,
        source=source,
    )


def _velocity(f: dict[str, Field]) -> np.ndarray:
    return f["velocity"].vector(2) if "velocity" in f else np.zeros(2)


def _read_camera(node: Field) -> tuple[LineCamera, np.ndarray]:
    f = node.object(
        required=("e", "w", "fov_angle", "pixels"),
        optional=("projection", "width", "velocity"),
    )
    e = f["e"].vector(2)
    w = f["w"].vector(2)
    if not np.any(w):
        raise f["w"].error("is the zero vector, so there is no view direction")
    camera = LineCamera(
        e=e,
        w=w,
        fov_angle=f["fov_angle"].number(gt=0, lt=180),
        pixels=f["pixels"].integer(ge=1, le=MAX_PIXELS),
        projection=f["projection"].string(PROJECTIONS) if "projection" in f else "perspective",
        width=f["width"].number(gt=0) if "width" in f else 2.0,
    )
    return camera, _velocity(f)


def _read_ball(node: Field) -> Ball:
    f = node.object(required=("center", "radius", "color"), optional=("velocity", "name"))
    return Ball(
        center=f["center"].vector(2),
        radius=f["radius"].number(gt=0),
        color=f["color"].color(),
        velocity=_velocity(f),
        name=f["name"].string() if "name" in f else None,
    )


def _read_billboard(node: Field, folder: Path) -> Billboard:
    f = node.object(
        required=("start", "end"), optional=("image", "row", "color", "velocity", "name")
    )
    start, end = f["start"].vector(2), f["end"].vector(2)
    if np.array_equal(start, end):
        raise f["end"].error("coincides with start, so the billboard has no length")
    node.exactly_one_of(f, "image", "color")
    if "row" in f and "image" not in f:
        raise f["row"].error('is only for billboards with an "image"')
    texture, row = None, 0
    if "image" in f:
        texture = Texture(folder / f["image"].string(), f["image"].source, f["image"].path)
        row = f["row"].integer(ge=0, le=texture.height - 1) if "row" in f else 0
    return Billboard(
        start=start,
        end=end,
        color=f["color"].color() if "color" in f else None,
        texture=texture,
        row=row,
        velocity=_velocity(f),
        name=f["name"].string() if "name" in f else None,
    )

"""Rendering in float32: the scene moved to the eye first.

float32 holds about 7 digits. A scene near 1e6 has coordinates whose float32 spacing is 0.06,
coarser than its details, so no formula could keep them. Rays, though, only ever need positions
*relative to the eye*: moved so that the eye is the origin (in float64, exactly as far as
float64 goes) and only then rounded to float32, the geometry keeps its 7 digits where it matters,
near the eye. The intersection math (raykit.spheres, raykit.planes, raykit.billboards) then runs
in whatever float type its arrays have.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from raykit.lights import AreaLight, PointLight
from raykit.scene import Scene


def eye_relative(scene: Scene, dtype: type = np.float32) -> Scene:
    """The scene moved so that the eye is at the origin, its objects' geometry in ``dtype``.

    The camera keeps float64 (its frame is computed once); object indices and order stay.
    """
    eye = np.asarray(scene.camera.eye, float)

    def moved(point) -> np.ndarray:
        return (np.asarray(point, float) - eye).astype(dtype)

    camera = replace(scene.camera, eye=np.zeros(3), lookat=np.asarray(scene.camera.lookat) - eye)
    spheres = tuple(
        replace(s, center=moved(s.center), radius=dtype(s.radius)) for s in scene.spheres
    )
    billboards = tuple(
        replace(
            b,
            upper_left=moved(b.upper_left),
            lower_left=moved(b.lower_left),
            upper_right=moved(b.upper_right),
        )
        for b in scene.billboards
    )
    lights = tuple(
        replace(light, position=moved(light.position))
        if isinstance(light, PointLight)
        else replace(light, corner=moved(light.corner))
        if isinstance(light, AreaLight)
        else light
        for light in scene.lights
    )
    return replace(scene, camera=camera, spheres=spheres, billboards=billboards, lights=lights)

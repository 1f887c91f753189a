"""A scene, as data: a camera, a background colour, spheres and billboards, and (stage 4) lights.

Stage 4 adds, all optional: ``lights`` (:mod:`raykit.lights`), ``ambient``, per-object materials
(:mod:`raykit.materials`), a ``shadows`` switch and ``max_depth`` for mirror bounces. A scene
without them renders exactly as format v1 always did.

Stage 5 (format v2) adds distributed ray tracing (FOCG 13.4): area lights
(:class:`raykit.lights.AreaLight`), a thin-lens camera (:mod:`raykit.camera`), glossy mirrors
(:mod:`raykit.mirrors`), motion blur, and how the render samples
(:class:`raykit.sampling.Sampling`: samples per pixel, the sampler, the seed, the shutter).
A scene with any of them is :attr:`Scene.distributed`; one without renders as before.

Scenes are read from files by :mod:`raykit.io.scene_json` (format v1, documented in
``docs/scene-format.md``) and :mod:`raykit.io.nff`. Geometry conventions live with the
objects: :mod:`raykit.camera`, :mod:`raykit.spheres`, :mod:`raykit.billboards`. Nothing here
is kept for speed but two answers the scene cannot change (:attr:`Scene.materials`,
:attr:`Scene.distributed`): the engine's arrays of a scene are :mod:`raykit.engine.arrays`.

Object indices. Wherever raykit reports "which object a ray hit" (the renderer's
``object_index`` image, diagrams, grading), object i counts the spheres first, in file order,
then the billboards: spheres are 0 .. S-1, billboards S .. S+B-1, and -1 is "nothing". The same
order breaks ties: of two objects hit at exactly the same t, the lower index wins.

Motion (for the 3D line-scan camera's sweep, :mod:`raykit.linescan.sweep3d`): an object may have
a ``velocity``, in scene units per scan, kept in :attr:`Scene.velocities` in object index order.
A render shows the scene as it stands (scan 0); scan m of a sweep sees every object moved by
m·velocity (:meth:`Scene.at`), as in the 2D line-scan scene (:mod:`raykit.linescan.scene`).
With a shutter (format v2's ``render.shutter``, motion blur) the velocity is per unit of time
and each ray sees the spheres at its own time T in the shutter interval, a sphere at c + T·v
(:func:`raykit.spheres.center_at`): the scene :attr:`Scene.moving`. Only spheres move in a
render; the loader refuses a billboard's velocity in a scene with a shutter.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from raykit.billboards import Billboard
from raykit.camera import Camera
from raykit.lights import AreaLight, Light
from raykit.materials import MaterialTable
from raykit.sampling import Sampling
from raykit.spheres import Sphere, SphereTable

DEFAULT_MAX_DEPTH = 3


@dataclass(frozen=True)
class Scene:
    """Everything the renderer needs; ``source`` names where it came from, for messages."""

    camera: Camera
    spheres: Sequence[Sphere] = ()  # a tuple, or the loader's columns (raykit.spheres.SphereTable)
    billboards: tuple[Billboard, ...] = ()
    background: np.ndarray = field(default_factory=lambda: np.zeros(3))
    source: str = "<scene>"
    lights: tuple[Light, ...] = ()
    ambient: np.ndarray | None = None
    shadows: bool = True
    max_depth: int = DEFAULT_MAX_DEPTH
    sampling: Sampling = Sampling()
    velocities: np.ndarray | None = None  # (K, 3) per scan, object index order; None: all still

    @property
    def objects(self) -> tuple[Sphere | Billboard, ...]:
        """All objects in index order (spheres, then billboards); see the module docstring."""
        return tuple(self.spheres) + tuple(self.billboards)

    @property
    def object_count(self) -> int:
        """K = S + B, the number of objects (without making :attr:`objects`)."""
        return len(self.spheres) + len(self.billboards)

    def only(self, ids: np.ndarray) -> Scene:
        """The scene with only the objects ``ids`` (scene indices, ascending), kept in index
        order, so that the nearest hit and the tie rule are the same among them."""
        spheres = len(self.spheres)
        return replace(
            self,
            spheres=tuple(self.spheres[i] for i in ids if i < spheres),
            billboards=tuple(self.billboards[i - spheres] for i in ids if i >= spheres),
            velocities=None if self.velocities is None else self.velocities[np.asarray(ids, int)],
        )

    def at(self, scan: float) -> Scene:
        """The scene as scan number ``scan`` sees it: every object moved by scan·velocity
        (the same scene when nothing moves)."""
        if self.velocities is None:
            return self
        shifts = scan * self.velocities
        spheres = len(self.spheres)
        return replace(
            self,
            spheres=tuple(
                replace(s, center=s.center + shift)
                for s, shift in zip(self.spheres, shifts[:spheres], strict=True)
            ),
            billboards=tuple(
                replace(
                    b,
                    upper_left=b.upper_left + shift,
                    lower_left=b.lower_left + shift,
                    upper_right=b.upper_right + shift,
                )
                for b, shift in zip(self.billboards, shifts[spheres:], strict=True)
            ),
        )

    @property
    def lit(self) -> bool:
        """Whether light is computed: the scene has lights or ambient light (else flat colours)."""
        return bool(self.lights) or self.ambient is not None

    @property
    def area_lights(self) -> int:
        """How many of the lights are area lights (:class:`raykit.lights.AreaLight`)."""
        return sum(isinstance(light, AreaLight) for light in self.lights)

    @property
    def moving(self) -> bool:
        """Whether rays see spheres move: a shutter, and a sphere with a non-zero velocity."""
        if self.sampling.shutter is None or self.velocities is None:
            return False
        return bool(np.any(self.velocities[: len(self.spheres)]))

    @property
    def blurred(self) -> bool:
        """Whether each ray takes its own time (:attr:`moving`, the shutter open a while)."""
        return self.moving and self.sampling.shutter[1] > self.sampling.shutter[0]

    @cached_property
    def distributed(self) -> bool:
        """Whether the render is distributed (stage 5): more than one sample per pixel of the
        scene's :class:`raykit.sampling.Sampling`, an area light, a lens (aperture > 0), a glossy
        mirror, or spheres moving while the shutter is open. Asked at each render, and of every
        object: answered once (the scene is frozen), as :attr:`materials` is made once."""
        return (
            self.sampling.samples_per_pixel > 1
            or self.area_lights > 0
            or self.camera.aperture > 0
            or self.materials.any_glossy
            or self.moving
        )

    @cached_property
    def materials(self) -> MaterialTable:
        """Every object's material as arrays, in object index order."""
        if isinstance(self.spheres, SphereTable):  # plain spheres all
            plain = MaterialTable.plain(len(self.spheres))
            return MaterialTable.stack(plain, MaterialTable.of(self.billboards))
        return MaterialTable.of(self.objects)

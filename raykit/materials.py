"""Materials: how a surface answers light (FOCG 4.5–4.9), one per sphere or billboard.

==========  =======  ===========================================================================
field       letter   meaning
==========  =======  ===========================================================================
diffuse     kd       Lambert reflectance, a colour. Default: the object's ``color``; for a
                     billboard with an ``image``, the texel's colour (an image *is* its diffuse
                     colour, so a textured billboard takes no ``diffuse``).
                     The ambient reflectance ka is kd too, as the book suggests.
specular    ks       Blinn-Phong highlight colour; default black (no highlight).
shininess   p        Blinn-Phong exponent: higher is a smaller, sharper highlight; default 32.
mirror      km       Ideal mirror reflectance, a colour; default black (no mirror rays).
glossiness  a        Stage 5 (FOCG 13.4.4): the side of the square a mirror's reflected ray is
                     perturbed within (:mod:`raykit.mirrors`), >= 0; default 0, the ideal mirror.
==========  =======  ===========================================================================

A scene with no ``lights`` and no ``ambient`` is unlit: an object shows its flat ``color``
(scene format v1), plus km times what its mirror reflects, if it is a mirror.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

DEFAULT_SHININESS = 32.0
FIELDS = ("diffuse", "has_diffuse", "specular", "shininess", "mirror", "glossiness")


def _black() -> np.ndarray:
    return np.zeros(3)


@dataclass(frozen=True)
class Material:
    """``diffuse`` (kd, None: the object's colour), ``specular`` (ks), ``shininess`` (p),
    ``mirror`` (km) and ``glossiness`` (a); colours ``(3,)`` in [0, 1]."""

    diffuse: np.ndarray | None = None
    specular: np.ndarray = field(default_factory=_black)
    shininess: float = DEFAULT_SHININESS
    mirror: np.ndarray = field(default_factory=_black)
    glossiness: float = 0.0

    @property
    def is_mirror(self) -> bool:
        return bool(np.any(self.mirror > 0))

    @property
    def is_shiny(self) -> bool:
        return bool(np.any(self.specular > 0))


PLAIN = Material()


@dataclass(frozen=True)
class MaterialTable:
    """The materials of K objects as arrays, for looking up many hits at once: ``diffuse (K, 3)``
    with ``has_diffuse (K,)`` (False: use the object's colour), ``specular (K, 3)``,
    ``shininess (K,)``, ``mirror (K, 3)``, ``glossiness (K,)``."""

    diffuse: np.ndarray
    has_diffuse: np.ndarray
    specular: np.ndarray
    shininess: np.ndarray
    mirror: np.ndarray
    glossiness: np.ndarray

    @classmethod
    def of(cls, objects) -> MaterialTable:
        materials = [o.material for o in objects]
        return cls(
            diffuse=np.array(
                [m.diffuse if m.diffuse is not None else _black() for m in materials]
            ).reshape(-1, 3),
            has_diffuse=np.array([m.diffuse is not None for m in materials], dtype=bool),
            specular=np.array([m.specular for m in materials], dtype=float).reshape(-1, 3),
            shininess=np.array([m.shininess for m in materials], dtype=float),
            mirror=np.array([m.mirror for m in materials], dtype=float).reshape(-1, 3),
            glossiness=np.array([m.glossiness for m in materials], dtype=float),
        )

    @classmethod
    def plain(cls, count: int) -> MaterialTable:
        """``count`` objects of the plain material (:data:`PLAIN`), without listing them."""
        return cls(
            diffuse=np.zeros((count, 3)),
            has_diffuse=np.zeros(count, dtype=bool),
            specular=np.zeros((count, 3)),
            shininess=np.full(count, PLAIN.shininess),
            mirror=np.zeros((count, 3)),
            glossiness=np.zeros(count),
        )

    @classmethod
    def stack(cls, *tables: MaterialTable) -> MaterialTable:
        """One table of the objects of ``tables``, in order."""
        return cls(*(np.concatenate([getattr(t, name) for t in tables]) for name in FIELDS))

    @property
    def any_mirror(self) -> bool:
        return bool(np.any(self.mirror > 0))

    @property
    def any_glossy(self) -> bool:
        """Whether some mirror is glossy (km > 0 and a > 0): its rays take uniform numbers."""
        glossy = self.glossiness > 0  # one number an object: read first, the rows only if need be
        return bool(glossy.any() and self.mirror[glossy].any())

    @property
    def any_shiny(self) -> bool:
        return bool(np.any(self.specular > 0))

"""Reading JSON scene files field by field, with one-line errors that name the field.

Every scene format in raykit (the 3D one in :mod:`raykit.scene`, the line-scan one in
:mod:`raykit.linescan.scene`) reads its file through :class:`Field`, so they all check types,
lengths, ranges, NaN and unknown keys the same way and word their errors the same way::

    scenes/bad.json: spheres[2].radius: must be > 0, got -1

The published JSON Schemas (``raykit/io/schemas/``) describe the same rules for editors; the tests
check that schema and loader accept and reject the same files. The loader does not call a
JSON Schema library itself: its messages are better, and it keeps ``raykit render`` quick to
start.
"""

from __future__ import annotations

import contextlib
import difflib
import gc
import json
import math
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from raykit.io.errors import SceneError

SceneT = TypeVar("SceneT")


def _shown(value: Any) -> str:
    """A short rendering of a JSON value for 'got ...' in messages."""
    if isinstance(value, float) and not math.isfinite(value):
        return {math.inf: "Infinity", -math.inf: "-Infinity"}.get(value, "NaN")
    try:
        text = json.dumps(value)
    except (TypeError, ValueError):
        text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _type_name(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    return "an object"


def read_json_file(path: str | Path) -> tuple[Any, str]:
    """Parse a JSON file; returns (data, source) where source names the file in messages."""
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise SceneError(source, "", "scene file not found") from None
    except IsADirectoryError:
        raise SceneError(source, "", "is a folder, not a scene file") from None
    except UnicodeDecodeError:
        raise SceneError(source, "", "not valid JSON: the file is not UTF-8 text") from None
    except OSError as exc:
        raise SceneError(source, "", f"scene file cannot be read ({exc.strerror})") from None
    try:
        with _no_cycle_collection():
            return json.loads(text), source
    except json.JSONDecodeError as exc:
        raise SceneError(
            source, "", f"not valid JSON: {exc.msg} (line {exc.lineno}, column {exc.colno})"
        ) from None
    except RecursionError:
        raise SceneError(source, "", "not valid JSON: nested too deeply") from None


@contextlib.contextmanager
def _no_cycle_collection() -> Iterator[None]:
    """Python's collector of reference cycles off meanwhile, if it was on: parsing a file makes a
    container for each of its objects and lists, none of them in a cycle, and the collector,
    woken every few hundred new containers, looks over all those made so far, again and again:
    a large part of loading a scene of many spheres."""
    was_on = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_on:
            gc.enable()


class Field:
    """A JSON value together with where it came from: ``source`` (file) and ``path``."""

    def __init__(self, value: Any, source: str, path: str = "") -> None:
        self.value = value
        self.source = source
        self.path = path

    def error(self, problem: str) -> SceneError:
        return SceneError(self.source, self.path, problem)

    def _child_path(self, key: str | int) -> str:
        if isinstance(key, int):
            return f"{self.path}[{key}]"
        return f"{self.path}.{key}" if self.path else key

    # -- containers -------------------------------------------------------------------------

    def object(self, required: tuple[str, ...], optional: tuple[str, ...] = ()) -> dict[str, Field]:
        """The value as an object: checks required keys and rejects unknown ones.

        Returns the present fields, keyed by name.
        """
        what = f"the {self.path} entry" if self.path else "the scene"
        if not isinstance(self.value, dict):
            raise self.error(f"{what} must be a JSON object, got {_type_name(self.value)}")
        known = required + optional
        for key in self.value:
            if key not in known:
                close = difflib.get_close_matches(key, known, n=1) or [
                    k
                    for k in known
                    if len(key) >= 2 and key.lower() in k  # "fov" -> fov_angle
                ]
                hint = f'; did you mean "{close[0]}"?' if close else f"; known: {', '.join(known)}"
                raise SceneError(self.source, self._child_path(key), "unknown field" + hint)
        for key in required:
            if key not in self.value:
                raise SceneError(self.source, self._child_path(key), "required field is missing")
        return {key: Field(v, self.source, self._child_path(key)) for key, v in self.value.items()}

    def exactly_one_of(self, fields: dict[str, Field], first: str, second: str) -> None:
        """Check that an object (read by :meth:`object`) has exactly one of two keys."""
        if (first in fields) == (second in fields):
            both = "both" if first in fields else "neither"
            raise self.error(f'needs exactly one of "{first}" and "{second}", got {both}')

    def items(self) -> list[Field]:
        """The value as a list of fields."""
        if not isinstance(self.value, list):
            raise self.error(f"must be a list, got {_type_name(self.value)}")
        return [Field(v, self.source, self._child_path(i)) for i, v in enumerate(self.value)]

    # -- scalars ----------------------------------------------------------------------------

    def number(
        self,
        *,
        gt: float | None = None,
        ge: float | None = None,
        lt: float | None = None,
        le: float | None = None,
    ) -> float:
        """A finite number within the given bounds."""
        value = self.value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(f"must be a number, got {_shown(value)}")
        try:
            number = float(value)
        except OverflowError:
            number = math.inf
        if not math.isfinite(number):
            raise self.error(f"must be a finite number, got {_shown(number)}")
        for bound, fails, word in (
            (gt, lambda b: number <= b, ">"),
            (ge, lambda b: number < b, ">="),
            (lt, lambda b: number >= b, "<"),
            (le, lambda b: number > b, "<="),
        ):
            if bound is not None and fails(bound):
                raise self.error(f"must be {word} {bound:g}, got {_shown(value)}")
        return number

    def integer(self, *, ge: int | None = None, le: int | None = None) -> int:
        """A whole number (JSON integer) within the given bounds."""
        value = self.value
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(f"must be a whole number, got {_shown(value)}")
        if ge is not None and value < ge:
            raise self.error(f"must be >= {ge}, got {_shown(value)}")
        if le is not None and value > le:
            raise self.error(f"must be <= {le}, got {_shown(value)}")
        return value

    def string(self, choices: tuple[str, ...] | None = None) -> str:
        """A string, optionally one of ``choices``."""
        if not isinstance(self.value, str):
            raise self.error(f"must be a string, got {_shown(self.value)}")
        if choices is not None and self.value not in choices:
            options = " or ".join(f'"{c}"' for c in choices)
            raise self.error(f"must be {options}, got {_shown(self.value)}")
        return self.value

    def boolean(self) -> bool:
        """true or false."""
        if not isinstance(self.value, bool):
            raise self.error(f"must be true or false, got {_shown(self.value)}")
        return self.value

    def vector(self, length: int, **bounds: float) -> np.ndarray:
        """A list of ``length`` finite numbers, ``(length,)`` float64; bounds apply to each."""
        if not isinstance(self.value, list):
            raise self.error(f"must be a list of {length} numbers, got {_shown(self.value)}")
        if len(self.value) != length:
            raise self.error(f"must have {length} numbers, got {len(self.value)}")
        return np.array([item.number(**bounds) for item in self.items()], dtype=float)

    def color(self) -> np.ndarray:
        """An [r, g, b] colour, each in [0, 1], ``(3,)``."""
        return self.vector(3, ge=0.0, le=1.0)

    def intensity(self) -> np.ndarray:
        """An [r, g, b] light intensity, each >= 0 (may exceed 1), ``(3,)``."""
        return self.vector(3, ge=0.0)


# Fields only one of the two JSON formats has, at the top and in the camera: enough to tell a
# 2D line-scan scene handed to the 3D loader (or the other way round) from a 3D scene with a typo
_MARKS = {
    "3d": ({"spheres", "lights", "ambient", "shadows", "max_depth"}, {"eye", "lookat", "up"}),
    "linescan": ({"balls", "scans"}, {"e", "w", "pixels"}),
}


def scene_kind(data: Any) -> str | None:
    """Which format parsed JSON ``data`` is: ``"3d"``, ``"linescan"``, or None when it has the
    distinctive fields of neither or of both (then the loader's own checks say what is wrong).

    A format's distinctive fields: for 3D, top-level ``spheres``, ``lights``, ``ambient``,
    ``shadows`` or ``max_depth``, or ``camera.eye``/``lookat``/``up``; for the line-scan format,
    top-level ``balls`` or ``scans``, or ``camera.e``/``w``/``pixels``."""
    if not isinstance(data, dict):
        return None
    camera = data.get("camera")
    keys = (set(data), set(camera) if isinstance(camera, dict) else set())
    found = [
        kind for kind, (top, in_camera) in _MARKS.items() if keys[0] & top or keys[1] & in_camera
    ]
    return found[0] if len(found) == 1 else None


_OTHER_FORMAT = {
    "3d": "a 3D scene (camera eye, lookat, up; spheres), not a 2D line-scan one: "
    "use raykit render or raykit diagram",
    "linescan": "a 2D line-scan scene (camera e, w, pixels; balls), not a 3D one: "
    "use raykit scan or raykit sweep",
}


def refuse_other_format(data: Any, source: str, expected: str) -> None:
    """Raise a one-line :class:`SceneError` when ``data`` is plainly the other format than
    ``expected`` ("3d" or "linescan"), naming the command that reads it."""
    kind = scene_kind(data)
    if kind is not None and kind != expected:
        raise SceneError(source, "", _OTHER_FORMAT[kind])


# the one way a scene format's file is opened and its top level read; each format's loader
# (raykit.io.scene_json, raykit.io.linescan_json) says only what its fields are


def read_scene_file(path: str | Path, from_dict: Callable[..., SceneT]) -> SceneT:
    """The scene ``from_dict(data, source=, folder=)`` builds from the JSON file at ``path``:
    the file named in every error, the images it names found beside it. The parsed file is made
    and dropped with the cycle collector off (:func:`_no_cycle_collection`): on again once it is
    gone, the collector does not look it over either."""
    with _no_cycle_collection():
        return _built(path, from_dict)


def _built(path: str | Path, from_dict: Callable[..., SceneT]) -> SceneT:
    data, source = read_json_file(path)
    return from_dict(data, source=source, folder=Path(path).parent)


def top_fields(
    data: Any, source: str, kind: str, required: tuple[str, ...], optional: tuple[str, ...]
) -> dict[str, Field]:
    """The top-level fields of a ``kind`` ("3d" or "linescan") scene: the other format refused
    naming its command, then the keys checked as :meth:`Field.object` checks them."""
    refuse_other_format(data, source, kind)
    return Field(data, source).object(required=required, optional=optional)

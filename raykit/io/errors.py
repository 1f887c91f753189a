"""The one error a user of raykit sees for bad input.

Every message is one line: ``<file>: <field path>: <what is wrong>``, for example
``scenes/bad.json: spheres[2].radius: must be > 0, got -1``. The CLI prints it and exits with
status 2; library callers catch it as a ``ValueError``.
"""

from __future__ import annotations


class SceneError(ValueError):
    """Bad input in a scene file or one of the files it names (textures included)."""

    def __init__(self, source: str, field: str, problem: str) -> None:
        self.source = source
        self.field = field
        self.problem = problem
        where = f"{source}: {field}" if field else source
        super().__init__(f"{where}: {problem}")

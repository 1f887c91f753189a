"""A practice test on disk: one folder of the starter kit's ``tests/expected/``.

``task.json`` says what to run (the task, its kind, the test's name and its spec),
``inputs.npz`` holds the inputs and ``expected.npz`` the reference results; a spec's
``folder`` (scene textures) is relative to the case's folder.
:mod:`raykit_grading.assignment.release` writes the cases; the kit's tests and its ``check.py``
(:mod:`raykit_grading.kit.selfcheck`) read them with :func:`read_case`, from the copy of this module
in ``tests/_grading/``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np


def located(spec: dict, folder: Path) -> dict:
    """The spec with its ``folder``, if it has one, made a path inside the case's folder."""
    spec = dict(spec)
    if "folder" in spec:
        spec["folder"] = str(Path(folder) / spec["folder"])
    return spec


def read_case(folder: Path) -> tuple[dict, dict, dict]:
    """``(order, inputs, expected)`` of the case in ``folder``: task.json with its spec
    :func:`located`, and the two npz files' arrays."""
    folder = Path(folder)
    order = json.loads((folder / "task.json").read_text())
    order["spec"] = located(order["spec"], folder)
    with np.load(folder / "inputs.npz") as data:
        inputs = {k: data[k] for k in data.files}
    with np.load(folder / "expected.npz") as data:
        expected = {k: data[k] for k in data.files}
    return order, inputs, expected

"""The reference's results of a grading test's draw, right or with a classic mistake made:
what the grader judges a submission against, and what the release's practice tests and
self-check diagnosis hold."""

from __future__ import annotations

import functools
import json
import tempfile
from pathlib import Path

import numpy as np

from raykit_grading.assignment.catalog import TESTS, GradingTest
from raykit_grading.assignment.mistakes import MISTAKES
from raykit_grading.kit import tasks


@functools.cache
def expected(test_name: str, seed: int | None, mistake: str | None = None) -> dict:
    """The reference results of a test's draw (``seed`` None: the public draw), optionally
    with a classic mistake made."""
    test = next(t for t in TESTS if t.name == test_name)
    spec, arrays, files = test.public_inputs() if seed is None else test.graded_inputs(seed)
    return reference_results(test, spec, arrays, files, mistake)


def reference_results(test: GradingTest, spec, arrays, files, mistake: str | None = None):
    """``test``'s task run here by the reference raykit on these inputs."""
    spec = json.loads(json.dumps(spec))
    with tempfile.TemporaryDirectory() as folder:
        if "folder" in spec:  # the reference reads the textures where the child would
            for relative, source in files.items():
                target = Path(folder) / relative
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(source.read_bytes())
            spec["folder"] = str(Path(folder) / spec["folder"])
        if mistake is None:
            return tasks.TASKS[test.task](spec, arrays)
        wrong = next(m for m in MISTAKES if m.key == mistake)
        image = test.kind == "image"
        with wrong.active(arrays=not image):
            outputs = tasks.TASKS[test.task](spec, arrays)
        if not image:
            return {k: np.asarray(v) for k, v in outputs.items()}
        return {k: wrong.after(v) for k, v in outputs.items()}


def array_mistakes(test: GradingTest, seed: int | None):
    """(what it says, the results, where it is made) of each classic mistake on this test's
    draw; a mistake the reference cannot make here (it fails) is left out."""
    for mistake in MISTAKES:
        try:
            results = expected(test.name, seed, mistake.key)
        except Exception:  # noqa: BLE001 - a patch that does not fit this task
            continue
        yield mistake.says, results, mistake.where

"""What runs inside the sandbox's child process: one task of the submission's code, arrays out.

    python -I -S child.py WORK_FOLDER

runs inside the sandbox (:mod:`raykit_grading.sandbox.base`). It reads ``task.json`` and
``inputs.npz`` from WORK_FOLDER (read-only), drops root if it has it, puts the submission and
the allowed libraries (numpy, Pillow) on ``sys.path`` and nothing else, runs the task (from
``tasks.py`` beside it, :mod:`raykit_grading.kit.tasks`, loaded by its path), and writes the results
as an ``.npz`` of plain arrays to a pipe the grader holds (never to a file: the grader reads
nothing back from the sandbox's disk).
"""

from __future__ import annotations

import importlib.util
import io
import json
import os
import sys
from pathlib import Path


def _drop_privileges(uid: int | None) -> None:
    """As root (grading on Gradescope), become the task's own unprivileged uid before any
    submitted code is imported; and never gain privileges again (no setuid programs)."""
    import ctypes

    if uid is not None and os.geteuid() == 0:
        os.setgroups([])
        os.setgid(uid)
        os.setuid(uid)
    if os.geteuid() == 0 and uid is not None:
        raise SystemExit("raykit grader: could not drop root")
    PR_SET_NO_NEW_PRIVS = 38
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0)


def _tasks(work: Path) -> dict:
    """:data:`raykit_grading.kit.tasks.TASKS`, from the copy the grader put in the work folder (the
    child runs isolated, ``-I``: no folder of its own is on its path)."""
    spec = importlib.util.spec_from_file_location("raykit_grading_tasks", work / "tasks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.TASKS


def _say(exc: BaseException, submission: str) -> None:
    """Print ``exc``'s traceback as Python would, with only the submission's frames: the
    grader's own (this file, tasks.py) tell a student nothing."""
    import traceback

    said = traceback.TracebackException.from_exception(exc)
    for part in (said, said.__cause__, said.__context__):
        if part is not None:
            part.stack = traceback.StackSummary.from_list(
                [frame for frame in part.stack if frame.filename.startswith(submission)]
            )
    print("".join(said.format()), end="", file=sys.stderr)


def main(work: Path) -> int:
    order = json.loads((work / "task.json").read_text())
    _drop_privileges(order.get("uid"))
    returned = os.fdopen(order["outputs_fd"], "wb")
    sys.path[:0] = [str(work / "submission"), *order["library_paths"]]
    import numpy as np  # only now, from the allowed paths

    with np.load(work / "inputs.npz", allow_pickle=False) as data:
        arrays = {k: data[k] for k in data.files}
    spec = order["spec"]
    if "folder" in spec:
        spec["folder"] = str(work / spec["folder"])
    task = _tasks(work)[order["task"]]
    try:
        outputs = task(spec, arrays)
    except Exception as exc:  # noqa: BLE001 - said as Python says it, in the student's frames
        _say(exc, str(work / "submission"))
        return 1
    packed = io.BytesIO()
    np.savez(packed, **{k: np.asarray(v) for k, v in outputs.items()})
    returned.write(packed.getvalue())
    returned.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1])))

"""A grader Python like the one the zip's ``setup.sh`` makes, that every uid can run.

``setup.sh`` makes ``/opt/raykit-grader``: a venv of the system's Python with only what
``raykit_grading/grader-requirements.txt`` pins. The tests that grade through the zip's
``run_autograder`` run it with such a Python, never with the one running the suite (which has
raykit installed, and so would hide a zip the grader cannot be imported from). It is made from
a Python outside ``/root`` (this machine's own lives under ``/root``, which uid 65534 cannot
enter), readable by every uid, so the same interpreter serves the normal-user way too.

Made once per requirements file and Python (kept in ``/tmp``, keyed by both), with pip from
the package index; where that cannot be done, :func:`grader_python` says why, and the tests
that need it skip saying so. ``RAYKIT_USER_PYTHON`` names one to use instead (it must have
numpy and Pillow, and be runnable by uid 65534).

:func:`instructor_python` is made the same way with raykit's own dependencies instead (those
``pip install -e .`` installed here, as for an instructor): ``batch`` as a normal user needs
matplotlib for its class report, which the zip's grader does not have.
"""

from __future__ import annotations

import fcntl
import hashlib
import os
import shutil
import subprocess
from pathlib import Path

from conftest import REPO

REQUIREMENTS = REPO / "raykit_grading" / "grader-requirements.txt"
CANDIDATES = ("/usr/bin/python3", "/usr/local/bin/python3")


def _base_python() -> str | None:
    for python in CANDIDATES:
        if os.access(python, os.X_OK) and not os.path.realpath(python).startswith("/root/"):
            return python
    return None


def grader_python() -> tuple[str | None, str]:
    """(the grader Python's path, "") or (None, why it could not be made)."""
    if os.environ.get("RAYKIT_USER_PYTHON"):
        return os.environ["RAYKIT_USER_PYTHON"], ""
    return _venv("grader", REQUIREMENTS.read_bytes(), ["-r", str(REQUIREMENTS)])


def instructor_python() -> tuple[str | None, str]:
    """(a Python with raykit's dependencies, that every uid can run, "") or (None, why not)."""
    from importlib.metadata import requires

    needs = [need for need in requires("raykit") or [] if "extra ==" not in need]
    return _venv("instructor", "\n".join(needs).encode(), needs)


def _venv(kind: str, what: bytes, pip_args: list[str]) -> tuple[str | None, str]:
    """A venv of the system's Python with ``pip install pip_args``, keyed by ``what`` and that
    Python, readable by every uid: (its python, "") or (None, why it could not be made)."""
    base = _base_python()
    if base is None:
        return None, f"no system Python outside /root to make the {kind}'s venv from"
    key = hashlib.sha256(what + os.path.realpath(base).encode())
    folder = Path("/tmp") / f"raykit-{kind}-python-{key.hexdigest()[:12]}"
    python = folder / "bin" / "python"
    with open(f"{folder}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if (folder / "complete").exists():
            return str(python), ""
        shutil.rmtree(folder, ignore_errors=True)
        made = subprocess.run([base, "-m", "venv", str(folder)], capture_output=True, text=True)
        if made.returncode != 0:
            return None, f"{base} -m venv failed (apt-get install python3-venv): {made.stderr}"
        pip = subprocess.run(
            [str(python), "-m", "pip", "install", "-q", "--disable-pip-version-check",
             *pip_args],
            capture_output=True, text=True, timeout=900,
        )  # fmt: skip
        if pip.returncode != 0:
            last = (pip.stderr.strip().splitlines() or ["no output"])[-1]
            return None, f"cannot install {' '.join(pip_args)} into a venv: {last}"
        subprocess.run(["chmod", "-R", "a+rX", str(folder)], check=True)
        (folder / "complete").touch()
    return str(python), ""

"""Which kind of sandbox grades here: the strongest that works (:data:`KINDS`), or the one
``RAYKIT_SANDBOX`` asks for."""

from __future__ import annotations

import os
from pathlib import Path

from raykit_grading.sandbox.base import Limits, Sandbox
from raykit_grading.sandbox.bubblewrap import Bubblewrap
from raykit_grading.sandbox.chroot import Chroot
from raykit_grading.sandbox.isolation import IsolationUnavailable

KINDS: dict[str, type[Sandbox]] = {
    kind.kind: kind for kind in (Bubblewrap, Chroot)
}  # strongest first


def choose_sandbox(
    submission: Path,
    workspace: Path,
    child_python: str | None = None,
    limits: Limits | None = None,
    kind: str | None = None,
) -> Sandbox:
    """The strongest sandbox that works here (:data:`KINDS`; ``kind``, or ``RAYKIT_SANDBOX``,
    asks for one), checked: its Python imports numpy and Pillow as the sandbox user;
    otherwise :class:`IsolationUnavailable`, saying why in one line and how to grade safely.

    Nothing weaker than the floor is ever used: as root, a chroot into the minimal tree, a uid
    of its own and the seccomp filter (Landlock on top where the kernel has it); as a normal
    user, bubblewrap only (a user's child shares the grader's uid, and without namespaces
    nothing would stop it from signalling the grader or outliving its test on a kernel without
    Landlock's scoping)."""
    wanted = kind or os.environ.get("RAYKIT_SANDBOX") or "auto"
    if wanted not in ("auto", *KINDS):
        raise IsolationUnavailable(
            f"RAYKIT_SANDBOX={wanted}: not a sandbox kind (auto, {', '.join(KINDS)})"
        )
    refused = []
    for name in KINDS if wanted == "auto" else (wanted,):
        # what every kind needs (the child's Python runs) is said as it is, once
        sandbox = KINDS[name](submission, workspace, child_python, limits)
        try:
            sandbox.check()
            return sandbox
        except IsolationUnavailable as exc:
            refused.append(f"{name}: {exc}")
    if len(refused) == 1:
        raise IsolationUnavailable(refused[0].split(": ", 1)[1])
    if os.geteuid() != 0:
        raise IsolationUnavailable(
            f"cannot isolate submissions as a normal user here ({refused[0]}); grade as "
            "root (sudo, or in a container as Gradescope does), or where unprivileged "
            "user namespaces are allowed"
        )
    raise IsolationUnavailable("no sandbox works here (" + "; ".join(refused) + ")")

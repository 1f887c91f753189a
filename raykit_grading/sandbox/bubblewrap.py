"""The bubblewrap sandbox: the task's child in namespaces of its own (mount, pid, network,
ipc, uts; a user namespace as a normal user), seeing only the Python it runs on, numpy,
Pillow, the staged submission and its read-only work folder
(:mod:`raykit_grading.sandbox.isolation` says what it is made of). As root its child drops to
its leased uid itself."""

from __future__ import annotations

import os
import resource
import subprocess
import tempfile
from pathlib import Path

from raykit_grading.sandbox.base import Sandbox, TaskFolder
from raykit_grading.sandbox.budgets import SIGNALS_PENDING
from raykit_grading.sandbox.isolation import WORK, find_bwrap, sandbox_arguments
from raykit_grading.sandbox.leftovers import remove_tree
from raykit_grading.sandbox.workspace import quarantine


class Bubblewrap(Sandbox):
    kind = "bubblewrap"
    test_depth = 2  # bwrap, its pid namespace's init, the test
    child_drops_uid = True

    def _prepare(self) -> None:
        self.bwrap = find_bwrap()
        self.description = "bubblewrap"

    def _task_folder(self) -> TaskFolder:
        """A folder of the grader's workspace, mounted read-only at :data:`WORK`."""
        work = Path(tempfile.mkdtemp(prefix="task-", dir=self.workspace))

        def clean():
            removal = remove_tree(work, quarantine(self.workspace))
            return removal, [removal.problem] if removal.problem else []

        return TaskFolder(work, WORK, clean)

    def _start(
        self, folder: TaskFolder, returned_write: int, uid: int | None
    ) -> tuple[subprocess.Popen, int]:
        """Start bwrap and the child in it: (the process, the read end of what it prints)."""
        command = [self.python.executable, "-I", "-S", "-B", f"{WORK}/child.py", folder.seen_as]
        printed_read, printed_write = os.pipe()
        # bwrap reads its arguments and its seccomp program from files, so that the child's
        # /proc shows neither
        with tempfile.TemporaryFile() as arguments, tempfile.TemporaryFile() as seccomp:
            seccomp.write(self.seccomp)
            seccomp.seek(0)
            listed = sandbox_arguments(self.python, folder.path, self.submission, self.as_root)
            listed += ["--seccomp", str(seccomp.fileno())]
            arguments.write(b"\0".join(a.encode() for a in listed) + b"\0")
            arguments.seek(0)
            try:
                child = subprocess.Popen(
                    [self.bwrap, "--args", str(arguments.fileno()), *command],
                    stdin=subprocess.DEVNULL,
                    stdout=printed_write,
                    stderr=printed_write,
                    env={"PATH": "/usr/bin:/bin"},
                    pass_fds=(returned_write, arguments.fileno(), seccomp.fileno()),
                    preexec_fn=self._limit,  # noqa: PLW1509 - the point
                )
            except BaseException:
                os.close(printed_read)
                raise
            finally:
                os.close(printed_write)
        return child, printed_read

    def _limit(self) -> None:
        """In the child, before exec: its own session and the limits (the uid comes later,
        inside the sandbox, from :mod:`raykit_grading.inside.child`)."""
        os.setsid()
        _prefer_me_when_memory_runs_out()
        limits = self.limits
        resource.setrlimit(resource.RLIMIT_CPU, (limits.cpu_seconds, limits.cpu_seconds))
        resource.setrlimit(resource.RLIMIT_AS, (limits.memory_bytes, limits.memory_bytes))
        resource.setrlimit(resource.RLIMIT_FSIZE, (limits.file_bytes, limits.file_bytes))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        resource.setrlimit(resource.RLIMIT_NOFILE, (limits.open_files, limits.open_files))
        resource.setrlimit(resource.RLIMIT_SIGPENDING, (SIGNALS_PENDING, SIGNALS_PENDING))
        if self.as_root:  # counted for the task's own uid, once the child has dropped to it
            resource.setrlimit(resource.RLIMIT_NPROC, (limits.processes, limits.processes))
        else:  # processes count per user: leave room for the ones the user already runs
            uid = os.getuid()
            running = 0
            for proc in Path("/proc").iterdir():
                try:
                    running += proc.name.isdigit() and proc.stat().st_uid == uid
                except OSError:
                    pass
            cap = running + limits.processes
            hard = resource.getrlimit(resource.RLIMIT_NPROC)[1]
            if hard != resource.RLIM_INFINITY:  # min() would take RLIM_INFINITY (-1) as less
                cap = min(cap, hard)
            resource.setrlimit(resource.RLIMIT_NPROC, (cap, cap))


def _prefer_me_when_memory_runs_out() -> None:
    """oom_score_adj 1000: if the container's memory runs out all the same, the kernel's
    OOM killer picks the child, not the grader (raising one's own score needs no privilege)."""
    try:
        with open("/proc/self/oom_score_adj", "w") as adj:
            adj.write("1000")
    except OSError:
        pass

"""Running one task of a submission in a sandbox, and taking back what it returns as untrusted.

Each task runs in a fresh child (:mod:`raykit_grading.inside.child`) inside a sandbox of its own,
of one of the kinds (:mod:`raykit_grading.sandbox.kinds`: bubblewrap, or a chroot where no
namespaces can be made): it sees only the Python it runs on, numpy, Pillow, the staged
submission and that task's read-only work folder; no network; nothing outlives the task.
:class:`Sandbox` is what every kind shares, written once; a kind's class says where the task's
folder is, what more it lays out there and how the child starts. The child gets:

* Python in isolated mode without ``site`` (``-I -S -B``): its path is the submission, then
  numpy and Pillow, then the standard library. The grader's reference raykit is not in its world.
* limits (:class:`Limits`): wall-clock time (then the whole sandbox is killed), CPU seconds,
  address space, threads (it is one process: the seccomp filter refuses a second), open
  files, the size of a file, queued signals, no cores; and the budgets the grader counts
  while it runs (:mod:`raykit_grading.sandbox.budgets`: memory with page tables, disk in its
  ``tmp/`` with the files it holds that have no name, the container's memory), past which it is
  stopped.
* a work folder of its own, made for that task and removed after it: a hidden test's inputs
  are never where a later (visible) test's child could find them.

What the child gives back is read as an untrusted stream, never from a path it could have
swapped for a link or a FIFO: its results come over a pipe the grader holds (at most
:attr:`Limits.returned_bytes`, within the wall time) as an ``.npz`` of at most
:attr:`Limits.returned_arrays` members, refused from its directory's end before the archive
is parsed, whose members must be stored (not compressed) ``.npy`` arrays, each header checked
against its size before any array is made (:mod:`raykit_grading.sandbox.returned`), all
within the test's wall time; what it prints comes over a second pipe, of which the first
:data:`OUTPUT_EXCERPT` bytes are kept.
"""

from __future__ import annotations

import json
import os
import selectors
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from raykit_grading.sandbox import confine
from raykit_grading.sandbox.budgets import (
    WATCH_SECONDS,
    ContainerMemory,
    Watch,
    disk_problem,
    kernel_share,
    memory_budget,
)
from raykit_grading.sandbox.isolation import (
    SITE,
    IsolationUnavailable,
    UidPool,
    probe_python,
    seccomp_filter,
)
from raykit_grading.sandbox.leftovers import DiskBudget, Removal, measure
from raykit_grading.sandbox.returned import read_returned

GRADER = Path(__file__).parents[1]
CHILD_SCRIPT = GRADER / "inside" / "child.py"
TASKS_SCRIPT = GRADER / "kit" / "tasks.py"  # the child loads it by path
OUTPUT_EXCERPT = 2000
# the preflight's probe runs only the grader's code and the libraries, never the submission's:
# it gets this long whatever a test may take, so that a loaded machine's slow start of Python
# and numpy is not taken for a sandbox that cannot work (which would grade nothing)
PROBE_SECONDS = 60.0


@dataclass(frozen=True)
class Limits:
    """What one task may use."""

    wall_seconds: float = 20.0
    cpu_seconds: int = 20
    memory_bytes: int = 2 * 1024**3  # M of raykit_grading.sandbox.budgets: cut to fit the container
    processes: int = 16  # threads of its one process (RLIMIT_NPROC counts them)
    open_files: int = 64  # shared by its threads (the seccomp filter sees to it)
    file_bytes: int = 64 * 1024**2
    disk: DiskBudget = DiskBudget()  # what its tmp/ may hold at once (bytes, entries, depth)
    # what it hands back: a test returns 3 arrays at most, the largest render 2 MB
    returned_bytes: int = 16 * 1024**2
    returned_arrays: int = 16


@dataclass
class ChildResult:
    """What came back: ``outputs`` (None if the child failed) and why it failed; ``left``
    what the child left in its ``tmp/`` that the grader had to force to remove ("" if
    nothing)."""

    outputs: dict[str, np.ndarray] | None
    problem: str = ""
    output: str = ""
    seconds: float = 0.0
    left: str = ""


@dataclass(frozen=True)
class TaskFolder:
    """One task's folder: its ``path`` here, the path the child sees it at, and what removes
    it after the task (what was removed, and the problems to say)."""

    path: Path
    seen_as: str
    clean: Callable[[], tuple[Removal, list[str]]]


class Sandbox:
    """Runs tasks of one staged submission in one kind of sandbox; make one per submission
    graded, with :func:`raykit_grading.sandbox.kinds.choose_sandbox`.

    ``workspace`` is a folder private to the grader (mode 700) for the tasks' work folders.
    :meth:`run` is the skeleton every kind shares: the task's folder filled, a uid leased, the
    child started, watched and read back as untrusted, what it left measured and removed. A
    kind says where the task's folder is (:meth:`_task_folder`), what more it lays out in it
    (:meth:`_lay_out`) and how the child starts (:meth:`_start`).
    """

    kind = ""  # its name in KINDS and RAYKIT_SANDBOX
    test_depth = 0  # how many generations below the process it starts the test's own is
    child_drops_uid = False  # the child takes its leased uid itself, inside the sandbox

    def __init__(
        self,
        submission: Path,
        workspace: Path,
        child_python: str | None = None,
        limits: Limits | None = None,
    ) -> None:
        self.submission = Path(submission)
        self.workspace = Path(workspace)
        self.container = confine.container_limits()
        self.limits = fit_to_container(limits or Limits(), self.container)
        self.memory = (
            ContainerMemory(
                self.container.memory_cgroup, self.container.memory_bytes, self.container.cgroup_v2
            )
            if self.container.memory_cgroup is not None
            else None
        )
        self.oom_before = self.oom_count()  # how often the container's OOM killer had fired
        self.python = probe_python(child_python or sys.executable)
        self.as_root = os.geteuid() == 0
        self.uids = UidPool() if self.as_root else None
        self.seccomp = seccomp_filter()
        self.description = ""  # what it is made of, e.g. "bubblewrap"; said by check()
        self.ready = False

    def check(self) -> None:
        """Preflight: make ready what this kind needs and run a probe in it, whose Python
        imports numpy and Pillow as the sandbox user; otherwise :class:`IsolationUnavailable`,
        saying why in one line."""
        self._prepare()
        self.ready = True
        ran = self.run("probe", {}, {}, wall_seconds=max(self.limits.wall_seconds, PROBE_SECONDS))
        if ran.outputs is None or "ok" not in ran.outputs:
            self.ready = False
            said = (ran.output.strip().splitlines() or [ran.problem])[-1]
            raise IsolationUnavailable(f"a sandbox could not run Python with numpy: {said}")

    def _prepare(self) -> None:
        """Make ready what this kind needs and set :attr:`description`, or raise
        :class:`IsolationUnavailable`."""
        raise NotImplementedError

    def run(
        self,
        task: str,
        spec: dict,
        arrays: dict[str, np.ndarray],
        files: dict[str, Path] | None = None,
        wall_seconds: float | None = None,
    ) -> ChildResult:
        """Run ``task`` of :mod:`raykit_grading.kit.tasks` on the submission, in a sandbox."""
        if not self.ready:
            self.check()
        place = self._task_folder()
        folder = place.path
        lease = self.uids.lease() if self.uids else None
        uid = lease.uid if lease else None
        returned_read, returned_write = os.pipe()
        try:
            try:
                order = {
                    "task": task,
                    "spec": spec,
                    "library_paths": [SITE],
                    "uid": uid if self.child_drops_uid else None,
                    "outputs_fd": returned_write,
                }
                self._fill(folder, order, arrays, files or {})
                self._lay_out(folder, uid)
                _writable_tmp(folder / "tmp", uid)
                wall = wall_seconds or self.limits.wall_seconds
                kills = self.oom_count()
                start, deadline = time.perf_counter(), time.monotonic() + wall
                child, printed_read = self._start(place, returned_write, uid)
            finally:
                os.close(returned_write)  # the child holds the only writing end now
            try:
                watch = Watch(self.limits, self.memory, child.pid, self.test_depth,
                              folder / "tmp", (uid, uid) if lease else None)  # fmt: skip
                returned, printed, status, why = _collect(
                    child, returned_read, printed_read, wall, self.limits.returned_bytes, watch
                )
            finally:
                _kill_group(child)
                os.close(printed_read)
        finally:
            os.close(returned_read)
            if lease is not None:
                lease.release()  # every process of the uid is dead after this
            left_over = measure(folder / "tmp", self.limits.disk)
            removal, problems = place.clean()
            for problem in problems:
                print(f"raykit_grading: {problem}", file=sys.stderr)
        why = self._killed_by_oom(kills) or why or disk_problem(left_over, self.limits.disk)
        return _result(returned, printed, status, why, time.perf_counter() - start, self.limits,
                       removal, deadline)  # fmt: skip

    def _task_folder(self) -> TaskFolder:
        """A folder for one task, made for it."""
        raise NotImplementedError

    def _lay_out(self, folder: Path, uid: int | None) -> None:
        """What this kind lays out in the task's folder besides the task (nothing here)."""

    def _start(
        self, folder: TaskFolder, returned_write: int, uid: int | None
    ) -> tuple[subprocess.Popen, int]:
        """Start the child in the sandbox: (the process, the read end of what it prints).
        Raises :class:`IsolationUnavailable` (its pipes closed) if it cannot."""
        raise NotImplementedError

    def oom_count(self) -> int | None:
        """How often the container's OOM killer has fired (None: no cgroup says)."""
        return self.memory.oom_kills() if self.memory is not None else None

    def _killed_by_oom(self, before: int | None) -> str:
        """Why the test failed if the container's OOM killer fired while it ran ("" if not)."""
        after = self.oom_count()
        if before is None or after is None or after <= before:
            return ""
        return "your code was killed: the container's memory ran out while it ran"

    def _fill(self, work: Path, order: dict, arrays, files: dict[str, Path]) -> None:
        """The task's folder: the child, the tasks, the inputs and what to run."""
        shutil.copyfile(CHILD_SCRIPT, work / "child.py")
        shutil.copyfile(TASKS_SCRIPT, work / "tasks.py")
        (work / "submission").mkdir()  # where the staged submission is mounted, read-only
        for relative, source in files.items():
            (work / relative).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(source, work / relative)  # the grader's own files, trusted
        np.savez(work / "inputs.npz", **arrays)
        (work / "task.json").write_text(json.dumps(order))
        for path in [work, *work.rglob("*")]:  # readable by the sandbox uid, writable by none
            os.chmod(path, 0o755 if path.is_dir() else 0o644)


def _writable_tmp(folder: Path, uid: int | None) -> None:
    """The one folder the child may write: its own (``uid``'s, as root), closed to others."""
    folder.mkdir(mode=0o700)
    if uid is not None:
        os.chown(folder, uid, uid)


def fit_to_container(limits: Limits, container: confine.ContainerLimits) -> Limits:
    """``limits`` with a test's memory cut to M of :mod:`raykit_grading.sandbox.budgets`: what the
    container leaves beside the grader (:data:`raykit_grading.sandbox.budgets.GRADER_MEMORY`) and
    what the kernel may hold for the test (:func:`raykit_grading.sandbox.budgets.kernel_share`), so
    that a test that takes all it may is stopped at its own limit (a MemoryError, or the grader's
    count: its test's zero) before the container runs out."""
    kernel = kernel_share(limits.open_files, limits.processes, limits.disk).total
    return replace(
        limits, memory_bytes=min(limits.memory_bytes, memory_budget(container.memory_bytes, kernel))
    )


PIPE_MOST_BYTES = 1 << 20  # the most a pipe holds that an unprivileged process enlarged


def _collect(child, returned_fd, printed_fd, wall_seconds, returned_limit, watch=None):
    """Read both pipes until the child is done, the wall time is up, it returns too much or
    ``watch()`` (called every :data:`WATCH_SECONDS`) says what it passed: (returned bytes,
    printed excerpt, exit status, why it was stopped or "")."""
    deadline = time.monotonic() + wall_seconds
    next_watch = time.monotonic() + WATCH_SECONDS
    returned, printed = bytearray(), bytearray()
    open_fds = {returned_fd, printed_fd}
    too_much = f"returned more than {returned_limit // 2**20} MB and was stopped"

    def take(fd: int) -> int:
        """Read a chunk of ``fd`` if one is there: its length (0 at the pipe's end, or when
        nothing is there now)."""
        try:
            chunk = os.read(fd, 1 << 16)
        except BlockingIOError:
            return 0
        if not chunk:
            open_fds.discard(fd)
        elif fd == returned_fd:
            returned.extend(chunk)
        elif len(printed) < OUTPUT_EXCERPT:
            printed.extend(chunk[: OUTPUT_EXCERPT - len(printed)])
        return len(chunk)

    with selectors.DefaultSelector() as selector:
        for fd in open_fds:
            os.set_blocking(fd, False)
            selector.register(fd, selectors.EVENT_READ)
        while child.poll() is None:
            now = time.monotonic()
            if watch is not None and now >= next_watch:
                passed = watch()
                if passed:
                    return bytes(returned), bytes(printed), None, passed
                next_watch = time.monotonic() + WATCH_SECONDS
            if deadline - now <= 0:
                return (bytes(returned), bytes(printed), None,
                        f"took longer than {wall_seconds:g} s and was stopped")  # fmt: skip
            wait = min(deadline - now, WATCH_SECONDS, 0.5)
            if not open_fds:
                try:
                    child.wait(timeout=wait)
                except subprocess.TimeoutExpired:
                    pass
                continue
            for key, _ in selector.select(timeout=wait):
                take(key.fd)
                if key.fd not in open_fds:  # at its end
                    selector.unregister(key.fd)
                if len(returned) > returned_limit:
                    return b"", bytes(printed), None, too_much
    # The child is done, and all it wrote is in the pipes: read what is there and stop, not
    # waiting for the pipes' end: a process it left behind may hold them open until it dies
    # with the test's uid, which must not cost the test its time. (A pipe holds at most
    # PIPE_MOST_BYTES: more is that process still writing.)
    for fd in list(open_fds):
        drained, read = 0, 1
        while drained < PIPE_MOST_BYTES and read:
            read = take(fd)
            drained += read
            if len(returned) > returned_limit:
                return b"", bytes(printed), None, too_much
    return bytes(returned), bytes(printed), child.returncode, ""


def _result(
    returned, printed, status, why, seconds, limits: Limits, removal: Removal, deadline=None
) -> ChildResult:
    output = printed.decode("utf-8", "replace")
    left = ""
    if removal.forced:
        left = (
            f"your code left {' and '.join(sorted(removal.forced))} in its tmp/ folder; "
            "the grader removed them"
        )
    if why:
        return ChildResult(None, why, output, seconds, left)
    if status != 0:
        return ChildResult(None, _describe_exit(status, output), output, seconds, left)
    try:
        outputs = read_returned(returned, limits.returned_bytes, limits.returned_arrays, deadline)
    except TimeoutError:
        return ChildResult(
            None, "took longer than its time, with the grader's reading of what it returned, "
            "and was stopped", output, seconds, left,
        )  # fmt: skip
    except ValueError as exc:
        return ChildResult(
            None, f"returned something that is not plain arrays ({exc})", output, seconds, left
        )
    return ChildResult(outputs, "", output, seconds, left)


def _kill_group(child: subprocess.Popen) -> None:
    """Kill bwrap and, through its pid namespace, everything the task started."""
    try:
        os.killpg(child.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    child.wait()


def _describe_exit(status: int, output: str) -> str:
    if status > 128 or status < 0:  # bwrap reports a signal as 128 + its number
        number = status - 128 if status > 128 else -status
        try:
            name = signal.Signals(number).name
        except ValueError:
            name = f"signal {number}"
        why = {
            "SIGXCPU": "used up its CPU time",
            "SIGXFSZ": "wrote a file larger than allowed",
            "SIGKILL": "was killed (too much memory or time?)",
            "SIGSEGV": "crashed",
        }.get(name, f"ended by {name}")
        return f"your code {why}"
    last = [line for line in output.strip().splitlines() if line.strip()]
    if last and "NotImplementedError" in last[-1]:
        return "not written yet: " + last[-1].split("NotImplementedError:", 1)[-1].strip()
    if last and "MemoryError" in last[-1]:
        return "your code used more memory than allowed"
    return f"your code stopped with an error: {last[-1] if last else f'exit status {status}'}"


__all__ = ["ChildResult", "IsolationUnavailable", "Limits", "Sandbox"]

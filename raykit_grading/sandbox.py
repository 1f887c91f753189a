"""Running one task of a submission in a sandbox, and taking back what it returns as untrusted.

Each task runs in a fresh child (:mod:`raykit_grading.child`) inside a sandbox of its own
(:mod:`raykit_grading.isolation`: it sees only the Python it runs on, numpy, Pillow, the staged
submission and that task's read-only work folder; no network; nothing outlives the task). The
child gets:

* Python in isolated mode without ``site`` (``-I -S -B``): its path is the submission, then
  numpy and Pillow, then the standard library. The grader's reference raykit is not in its world.
* limits (:class:`Limits`): wall-clock time (then the whole sandbox is killed), CPU seconds,
  address space, processes, the size of a file, a private ``/tmp`` of a fixed size, no cores.
* a work folder of its own, made for that task and removed after it: a hidden test's inputs
  are never where a later (visible) test's child could find them.

What the child gives back is read as an untrusted stream, never from a path it could have
swapped for a link or a FIFO: its results come over a pipe the grader holds (at most
:attr:`Limits.returned_bytes`, within the wall time) as an ``.npz`` whose members must be
stored (not compressed) ``.npy`` arrays, each header checked against its size before any
array is made (:func:`read_returned`; ``allow_pickle=False``); what it prints comes over a
second pipe, of which the first :data:`OUTPUT_EXCERPT` bytes are kept.
"""

from __future__ import annotations

import io
import json
import os
import resource
import selectors
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from raykit_grading.isolation import (
    SITE,
    WORK,
    IsolationUnavailable,
    UidPool,
    find_bwrap,
    probe_python,
    sandbox_arguments,
    seccomp_filter,
)

CHILD_SCRIPT = Path(__file__).with_name("child.py")
OUTPUT_EXCERPT = 2000


@dataclass(frozen=True)
class Limits:
    """What one task may use."""

    wall_seconds: float = 20.0
    cpu_seconds: int = 20
    memory_bytes: int = 2 * 1024**3
    processes: int = 16
    file_bytes: int = 64 * 1024**2
    tmp_bytes: int = 64 * 1024**2
    returned_bytes: int = 64 * 1024**2


@dataclass
class ChildResult:
    """What came back: ``outputs`` (None if the child failed) and why it failed."""

    outputs: dict[str, np.ndarray] | None
    problem: str = ""
    output: str = ""
    seconds: float = 0.0


class Sandbox:
    """Runs tasks of one staged submission; make one per submission graded.

    ``workspace`` is a folder private to the grader (mode 700) for the tasks' work folders.
    Raises :class:`IsolationUnavailable` when no sandbox can be made here.
    """

    def __init__(
        self,
        submission: Path,
        workspace: Path,
        child_python: str | None = None,
        limits: Limits | None = None,
    ) -> None:
        self.submission = Path(submission)
        self.workspace = Path(workspace)
        self.limits = limits or Limits()
        self.bwrap = find_bwrap()
        self.python = probe_python(child_python or sys.executable)
        self.as_root = os.geteuid() == 0
        self.uids = UidPool() if self.as_root else None
        self.seccomp = seccomp_filter()

    def check(self) -> None:
        """Preflight: a sandbox can be made and its Python imports numpy and Pillow, as the
        sandbox user; otherwise :class:`IsolationUnavailable`, saying why in one line."""
        ran = self.run("probe", {}, {})
        if ran.outputs is None or "ok" not in ran.outputs:
            said = (ran.output.strip().splitlines() or [ran.problem])[-1]
            raise IsolationUnavailable(f"a sandbox could not run Python with numpy: {said}")

    def run(
        self,
        task: str,
        spec: dict,
        arrays: dict[str, np.ndarray],
        files: dict[str, Path] | None = None,
        wall_seconds: float | None = None,
    ) -> ChildResult:
        """Run ``task`` of :mod:`raykit_grading.child` on the submission, in a sandbox."""
        work = Path(tempfile.mkdtemp(prefix="task-", dir=self.workspace))
        lease = self.uids.lease() if self.uids else None
        returned_read, returned_write = os.pipe()
        try:
            try:
                order = {
                    "task": task,
                    "spec": spec,
                    "library_paths": [SITE],
                    "uid": lease.uid if lease else None,
                    "outputs_fd": returned_write,
                }
                self._fill(work, order, arrays, files or {})
                start = time.perf_counter()
                child, printed_read = self._start(work, returned_write)
            finally:
                os.close(returned_write)  # the child holds the only writing end now
            try:
                returned, printed, status, why = _collect(
                    child,
                    returned_read,
                    printed_read,
                    wall_seconds or self.limits.wall_seconds,
                    self.limits.returned_bytes,
                )
            finally:
                _kill_group(child)
                os.close(printed_read)
        finally:
            os.close(returned_read)
            if lease is not None:
                lease.release()
            shutil.rmtree(work, ignore_errors=True)
        return _result(returned, printed, status, why, time.perf_counter() - start, self.limits)

    def _fill(self, work: Path, order: dict, arrays, files: dict[str, Path]) -> None:
        shutil.copyfile(CHILD_SCRIPT, work / "child.py")
        (work / "submission").mkdir()  # where the staged submission is mounted, read-only
        for relative, source in files.items():
            (work / relative).parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(source, work / relative)  # the grader's own files, trusted
        np.savez(work / "inputs.npz", **arrays)
        (work / "task.json").write_text(json.dumps(order))
        for path in [work, *work.rglob("*")]:  # readable by the sandbox uid, writable by none
            os.chmod(path, 0o755 if path.is_dir() else 0o644)

    def _start(self, work: Path, returned_write: int) -> tuple[subprocess.Popen, int]:
        """Start bwrap and the child in it: (the process, the read end of what it prints)."""
        command = [self.python.executable, "-I", "-S", "-B", f"{WORK}/child.py", WORK]
        printed_read, printed_write = os.pipe()
        # bwrap reads its arguments and its seccomp program from files, so that the child's
        # /proc shows neither
        with tempfile.TemporaryFile() as arguments, tempfile.TemporaryFile() as seccomp:
            seccomp.write(self.seccomp)
            seccomp.seek(0)
            listed = sandbox_arguments(
                self.python, work, self.submission, self.limits.tmp_bytes, self.as_root
            )
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
        inside the sandbox, from :mod:`raykit_grading.child`)."""
        os.setsid()
        limits = self.limits
        resource.setrlimit(resource.RLIMIT_CPU, (limits.cpu_seconds, limits.cpu_seconds))
        resource.setrlimit(resource.RLIMIT_AS, (limits.memory_bytes, limits.memory_bytes))
        resource.setrlimit(resource.RLIMIT_FSIZE, (limits.file_bytes, limits.file_bytes))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
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
            cap = min(running + limits.processes, resource.getrlimit(resource.RLIMIT_NPROC)[1])
            if cap > 0:
                resource.setrlimit(resource.RLIMIT_NPROC, (cap, cap))


def _collect(child, returned_fd, printed_fd, wall_seconds, returned_limit):
    """Read both pipes until the child is done, the wall time is up or it returns too much:
    (returned bytes, printed excerpt, exit status, why it was stopped or "")."""
    deadline = time.monotonic() + wall_seconds
    returned, printed = bytearray(), bytearray()
    open_fds = {returned_fd, printed_fd}
    with selectors.DefaultSelector() as selector:
        for fd in open_fds:
            os.set_blocking(fd, False)
            selector.register(fd, selectors.EVENT_READ)
        while open_fds or child.poll() is None:
            left = deadline - time.monotonic()
            if left <= 0:
                return (
                    bytes(returned),
                    bytes(printed),
                    None,
                    (f"took longer than {wall_seconds:g} s and was stopped"),
                )
            if not open_fds:
                try:
                    child.wait(timeout=min(left, 0.5))
                except subprocess.TimeoutExpired:
                    pass
                continue
            for key, _ in selector.select(timeout=min(left, 0.5)):
                try:
                    chunk = os.read(key.fd, 1 << 16)
                except BlockingIOError:
                    continue
                if not chunk:
                    selector.unregister(key.fd)
                    open_fds.discard(key.fd)
                elif key.fd == returned_fd:
                    returned += chunk
                    if len(returned) > returned_limit:
                        return (
                            b"",
                            bytes(printed),
                            None,
                            (f"returned more than {returned_limit // 2**20} MB and was stopped"),
                        )
                elif len(printed) < OUTPUT_EXCERPT:
                    printed += chunk[: OUTPUT_EXCERPT - len(printed)]
    return bytes(returned), bytes(printed), child.returncode, ""


def _result(returned, printed, status, why, seconds, limits: Limits) -> ChildResult:
    output = printed.decode("utf-8", "replace")
    if why:
        return ChildResult(None, why, output, seconds)
    if status != 0:
        return ChildResult(None, _describe_exit(status, output), output, seconds)
    try:
        outputs = read_returned(returned, limits.returned_bytes)
    except ValueError as exc:
        return ChildResult(
            None, f"returned something that is not plain arrays ({exc})", output, seconds
        )
    return ChildResult(outputs, "", output, seconds)


def _kill_group(child: subprocess.Popen) -> None:
    """Kill bwrap and, through its pid namespace, everything the task started."""
    try:
        os.killpg(child.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    child.wait()


def read_returned(data: bytes, limit: int) -> dict[str, np.ndarray]:
    """The arrays in an ``.npz`` a child returned, read as hostile input.

    Every member must be a stored (uncompressed) ``name.npy`` whose header's shape and dtype
    account for exactly the bytes that follow it, plain numbers or booleans, and all of them
    together at most ``limit`` bytes; so nothing is inflated or allocated beyond what was
    actually sent. Raises ValueError saying what is wrong.
    """
    if len(data) > limit:
        raise ValueError(f"more than {limit} bytes")
    try:
        return _read_npz(data, limit)
    except ValueError:
        raise
    except Exception as exc:  # noqa: BLE001 - whatever a hostile archive makes a parser do
        raise ValueError(f"unreadable: {type(exc).__name__}") from None


def _read_npz(data: bytes, limit: int) -> dict[str, np.ndarray]:
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
    except zipfile.BadZipFile as exc:
        raise ValueError(f"not an .npz: {exc}") from None
    arrays = {}
    with archive:
        members = archive.infolist()
        if sum(m.file_size for m in members) > limit:
            raise ValueError("its arrays are larger than allowed")
        for member in members:
            if (
                member.compress_type != zipfile.ZIP_STORED
                or member.file_size != member.compress_size
            ):
                raise ValueError(f"{member.filename} is compressed")
            if not member.filename.endswith(".npy"):
                raise ValueError(f"{member.filename} is not an array")
            with archive.open(member) as stream:
                version = np.lib.format.read_magic(stream)
                read_header = {
                    (1, 0): np.lib.format.read_array_header_1_0,
                    (2, 0): np.lib.format.read_array_header_2_0,
                }.get(version)
                if read_header is None:
                    raise ValueError(f"{member.filename}: .npy version {version}")
                shape, fortran, dtype = read_header(stream)
                if dtype.kind not in "biuf" or dtype.hasobject:
                    raise ValueError(f"{member.filename}: values of type {dtype}")
                size = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
                if stream.tell() + size != member.file_size:
                    raise ValueError(f"{member.filename}: its header does not match its size")
                array = np.frombuffer(stream.read(size), dtype=dtype)
                array = array.reshape(shape, order="F" if fortran else "C")
            arrays[member.filename[: -len(".npy")]] = array
    return arrays


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


__all__ = ["ChildResult", "IsolationUnavailable", "Limits", "Sandbox", "read_returned"]

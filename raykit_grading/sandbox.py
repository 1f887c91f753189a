"""Running a submission's code in a child process that can do nothing but hand back arrays.

Each task runs in a fresh child (:mod:`raykit_grading.child`) in a fresh work folder holding a
copy of
the submission's ``raykit`` package, the task's inputs and any texture files; nothing else of
the grader's is there. The child gets:

* Python in isolated mode without ``site`` (``-I -S``): its path is the submission, then a
  folder of links to numpy and Pillow only, then the standard library. The grader's reference
  raykit is not on it.
* limits (:class:`Limits`): wall-clock time (then the whole process group is killed), CPU
  seconds, address space, processes, the size of any file it writes (stdout and stderr go to
  files, so printing megabytes ends the child, not the grader), no core dumps.
* when the grader runs as root (Gradescope does): an unprivileged uid of its own (one per
  grader process, from :data:`SANDBOX_UIDS`), so it cannot read the grader's files, the
  references or the hidden scenes, nor write the results, and the grader can kill every
  process that uid has left behind. Its Python must then be one any user may run
  (``child_python``; Gradescope's ``setup.sh`` makes one).

The parent reads back ``outputs.npz`` with ``allow_pickle=False`` and checks every array's
shape, type and values itself (:func:`raykit_grading.grade.check_arrays`); nothing the child says is
trusted beyond that.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

CHILD_SCRIPT = Path(__file__).with_name("child.py")
SANDBOX_UIDS = range(50000, 60000)  # unprivileged uids the grader runs submissions as, as root
OUTPUT_EXCERPT = 2000


@dataclass(frozen=True)
class Limits:
    """What one task may use."""

    wall_seconds: float = 20.0
    cpu_seconds: int = 20
    memory_bytes: int = 2 * 1024**3
    processes: int = 64
    file_bytes: int = 64 * 1024**2


@dataclass(frozen=True)
class SandboxUser:
    pw_name: str
    pw_uid: int
    pw_gid: int


@dataclass
class ChildResult:
    """What came back: ``outputs`` (None if the child failed) and why it failed."""

    outputs: dict[str, np.ndarray] | None
    problem: str = ""
    output: str = ""
    seconds: float = 0.0


def _library_paths(python: str) -> list[str]:
    """Folders that hold numpy and Pillow (and their bundled .libs) for ``python``."""
    code = (
        "import json, numpy, PIL, pathlib;"
        "print(json.dumps([str(pathlib.Path(m.__file__).parent.parent) for m in (numpy, PIL)]))"
    )
    run = subprocess.run([python, "-I", "-c", code], capture_output=True, text=True, timeout=60)
    if run.returncode != 0:
        raise RuntimeError(f"{python} cannot import numpy and Pillow: {run.stderr.strip()[-300:]}")
    return json.loads(run.stdout)


class Sandbox:
    """Runs tasks in children; make one per grading run (it builds the library folder once)."""

    def __init__(self, child_python: str, limits: Limits | None = None) -> None:
        self.python = child_python
        self.limits = limits or Limits()
        self.user = self._sandbox_user() if os.geteuid() == 0 else None
        self._libraries = Path(tempfile.mkdtemp(prefix="raykit-libraries-"))
        os.chmod(self._libraries, 0o755)
        for folder in dict.fromkeys(_library_paths(child_python)):
            for name in ("numpy", "PIL", "numpy.libs", "pillow.libs"):
                if (Path(folder) / name).exists() and not (self._libraries / name).exists():
                    (self._libraries / name).symlink_to(Path(folder) / name)
        if self.user is not None:
            self._check_user_can_run_python()
            self._warn_if_grader_is_readable()

    def close(self) -> None:
        shutil.rmtree(self._libraries, ignore_errors=True)

    def __enter__(self) -> Sandbox:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    @staticmethod
    def _sandbox_user() -> SandboxUser:
        """An unprivileged uid and gid for this grader's children alone.

        A uid of its own, not shared with other graders running at the same time, so that
        killing "every process of the sandbox user" after a task never hits another grader's
        child. It needs no entry in /etc/passwd: as root, setuid to any uid works.
        """
        uid = SANDBOX_UIDS.start + os.getpid() % len(SANDBOX_UIDS)
        return SandboxUser(f"uid {uid}", uid, uid)

    def _check_user_can_run_python(self) -> None:
        work = Path(tempfile.mkdtemp(prefix="raykit-probe-"))
        os.chown(work, self.user.pw_uid, self.user.pw_gid)
        try:
            probe = self.run_raw([self.python, "-I", "-S", "-c", "print('ok')"], work)
        finally:
            shutil.rmtree(work, ignore_errors=True)
        if probe[0] != 0:
            raise RuntimeError(
                f"as root, submissions run as {self.user.pw_name}, which cannot run "
                f"{self.python}; give --child-python a Python that user may run "
                "(e.g. a venv made with /usr/bin/python3 and numpy, Pillow installed)"
            )

    def _warn_if_grader_is_readable(self) -> None:
        """The user separation protects only files that user cannot read (setup.sh closes
        /autograder/source); say so when the grader's own folder is open to it."""
        grader = Path(__file__).resolve().parent.parent
        for folder in [grader, *grader.parents]:
            mode = folder.stat().st_mode
            if not mode & 0o001:  # a folder on the way that others cannot enter
                return
        print(
            f"warning: {grader} is readable by user {self.user.pw_name}: a submission could "
            "read the grader and its hidden scenes; close it (chmod 700) as Gradescope's "
            "setup.sh does",
            file=sys.stderr,
        )

    def _limit(self) -> None:
        """In the child, before exec: its own session, the limits, then the unprivileged user."""
        os.setsid()
        limits = self.limits
        resource.setrlimit(resource.RLIMIT_CPU, (limits.cpu_seconds, limits.cpu_seconds))
        resource.setrlimit(resource.RLIMIT_AS, (limits.memory_bytes, limits.memory_bytes))
        resource.setrlimit(resource.RLIMIT_FSIZE, (limits.file_bytes, limits.file_bytes))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        if self.user is not None:
            os.setgroups([])
            os.setgid(self.user.pw_gid)
            resource.setrlimit(resource.RLIMIT_NPROC, (limits.processes, limits.processes))
            os.setuid(self.user.pw_uid)
        else:  # processes count per user: leave room for the ones the user already runs
            running = sum(1 for p in Path("/proc").iterdir() if p.name.isdigit())
            cap = min(running + limits.processes, resource.getrlimit(resource.RLIMIT_NPROC)[0])
            if cap > 0:
                resource.setrlimit(resource.RLIMIT_NPROC, (cap, cap))

    def run_raw(self, command: list[str], work: Path) -> tuple[int | None, str, float]:
        """Run ``command`` in ``work`` under the limits: (exit status or None, output, s)."""
        out_path = work / "child-output.txt"
        env = {
            "PATH": "/usr/bin:/bin",
            "OPENBLAS_NUM_THREADS": "1",
            "OMP_NUM_THREADS": "1",
            "MKL_NUM_THREADS": "1",
            "PYTHONDONTWRITEBYTECODE": "1",
            "HOME": str(work),
            "MPLBACKEND": "Agg",
        }
        start = time.perf_counter()
        with open(out_path, "wb") as out:
            child = subprocess.Popen(
                command,
                cwd=work,
                stdin=subprocess.DEVNULL,
                stdout=out,
                stderr=subprocess.STDOUT,
                env=env,
                preexec_fn=self._limit,
            )  # noqa: PLW1509 - the point
            try:
                status = child.wait(timeout=self.limits.wall_seconds)
            except subprocess.TimeoutExpired:
                status = None
            self._kill_everything(child.pid)
            if status is None:
                child.wait()
        seconds = time.perf_counter() - start
        with open(out_path, "rb") as out:
            text = out.read(OUTPUT_EXCERPT).decode("utf-8", "replace")
        return status, text, seconds

    def _kill_everything(self, pid: int) -> None:
        """Kill the child's process group and, as root, every process of the sandbox user."""
        try:
            os.killpg(pid, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass
        if self.user is None:
            return
        for _ in range(3):  # a fork bomb may still be forking between sweeps
            for proc in Path("/proc").iterdir():
                if proc.name.isdigit():
                    try:
                        if proc.stat().st_uid == self.user.pw_uid:
                            os.kill(int(proc.name), signal.SIGKILL)
                    except (FileNotFoundError, ProcessLookupError, PermissionError):
                        pass

    def run(
        self,
        submission: Path,
        task: str,
        spec: dict,
        arrays: dict[str, np.ndarray],
        files: dict[str, Path] | None = None,
    ) -> ChildResult:
        """Run ``task`` of :mod:`raykit_grading.child` on the submission's ``raykit`` package."""
        work = Path(tempfile.mkdtemp(prefix="raykit-child-"))
        try:
            shutil.copytree(
                submission,
                work / "submission" / "raykit",
                ignore=shutil.ignore_patterns("__pycache__"),
                symlinks=False,
            )
            shutil.copy(CHILD_SCRIPT, work / "child.py")
            for relative, source in (files or {}).items():
                (work / relative).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy(source, work / relative)
            np.savez(work / "inputs.npz", **arrays)
            order = {"task": task, "spec": spec, "library_paths": [str(self._libraries)]}
            (work / "task.json").write_text(json.dumps(order))
            if self.user is not None:
                for path in [work, *work.rglob("*")]:
                    os.chown(path, self.user.pw_uid, self.user.pw_gid, follow_symlinks=False)
            status, output, seconds = self.run_raw(
                [self.python, "-I", "-S", str(work / "child.py"), str(work)], work
            )
            if status is None:
                return ChildResult(
                    None,
                    f"took longer than {self.limits.wall_seconds:g} s and was stopped",
                    output,
                    seconds,
                )
            if status != 0:
                return ChildResult(None, _describe_exit(status, output), output, seconds)
            try:
                with np.load(work / "outputs.npz", allow_pickle=False) as data:
                    outputs = {k: data[k] for k in data.files}
            except Exception as exc:  # noqa: BLE001 - whatever the child left, it failed
                return ChildResult(
                    None,
                    f"returned something that is not plain arrays ({exc})",
                    output,
                    seconds,
                )
            return ChildResult(outputs, "", output, seconds)
        finally:
            shutil.rmtree(work, ignore_errors=True)


def _describe_exit(status: int, output: str) -> str:
    if status < 0:
        name = signal.Signals(-status).name
        why = {
            "SIGXCPU": "used up its CPU time",
            "SIGXFSZ": "wrote more output than allowed",
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

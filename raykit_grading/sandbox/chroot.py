"""The chroot sandbox, for where no namespaces can be made (Docker's default confinement, as
on Gradescope): the task's child chrooted into the minimal tree, as a uid of its own, under the
seccomp filter and Landlock where the kernel has it (:mod:`raykit_grading.sandbox.confine`
says what it is made of). It needs root."""

from __future__ import annotations

import os
import resource
import shutil
import subprocess
import sys
from pathlib import Path

from raykit_grading.sandbox import confine
from raykit_grading.sandbox.base import Sandbox, TaskFolder
from raykit_grading.sandbox.budgets import SIGNALS_PENDING
from raykit_grading.sandbox.isolation import IsolationUnavailable, child_environment
from raykit_grading.sandbox.leftovers import remove_tree


class Chroot(Sandbox):
    kind = "chroot"
    test_depth = 0  # the test's own process is the one it starts
    child_drops_uid = False  # it is the task's uid before child.py starts

    def _prepare(self) -> None:
        if not self.as_root:
            raise IsolationUnavailable("a chroot sandbox needs root")
        self.tree = confine.chroot_tree(self.python)
        self.landlock = confine.landlock_abi()
        made_of = ["chroot", "uid"]
        if self.landlock:
            made_of.append(f"landlock{self.landlock}")
        self.description = "+".join([*made_of, "seccomp"])

    def _task_folder(self) -> TaskFolder:
        """A slot of the tree (:func:`raykit_grading.sandbox.confine.lease_slot`), emptied and
        let go after the task."""
        slot, problems = confine.lease_slot(self.tree)
        for problem in problems:
            print(f"raykit_grading: {problem}", file=sys.stderr)

        def clean():
            removal = remove_tree(slot.outside / "tmp", self.tree.parent / confine.QUARANTINE)
            problems = slot.empty() + ([removal.problem] if removal.problem else [])
            slot.release()
            return removal, problems

        return TaskFolder(slot.outside, slot.inside, clean)

    def _lay_out(self, folder: Path, uid: int | None) -> None:
        """The staged submission copied in (no mount here), everything readable by the task's
        uid and the folder closed to every other."""
        (folder / "submission").rmdir()
        shutil.copytree(self.submission, folder / "submission", True, copy_function=_link_or_copy)
        for path in folder.rglob("*"):
            os.chmod(path, 0o755 if path.is_dir() else 0o644)
        os.chown(folder, 0, uid)  # its uid may read it, no other uid enter it
        os.chmod(folder, 0o750)

    def _start(
        self, folder: TaskFolder, returned_write: int, uid: int | None
    ) -> tuple[subprocess.Popen, int]:
        inside = folder.seen_as
        plan = confine.ChildConfinement(
            tree=str(self.tree),
            folder=inside,
            uid=uid,
            rlimits=self._rlimits(),
            landlock_abi=self.landlock,
            landlock_read_execute=tuple(confine.top_entries(self.tree)),
            seccomp=self.seccomp,
        )
        command = [self.python.executable, "-I", "-S", "-B", f"{inside}/child.py", inside]
        printed_read, printed_write = os.pipe()
        try:
            child = subprocess.Popen(
                command,
                stdin=subprocess.DEVNULL,
                stdout=printed_write,
                stderr=printed_write,
                env=child_environment(f"{inside}/tmp"),
                pass_fds=(returned_write,),
                preexec_fn=lambda: _confine_or_say(plan),  # noqa: PLW1509 - the point
            )
        except subprocess.SubprocessError:
            os.close(printed_write)
            said = os.read(printed_read, 2000).decode(errors="replace").strip()
            os.close(printed_read)
            raise IsolationUnavailable(
                f"the chroot sandbox could not start a child: {said or 'no reason given'}"
            ) from None
        except BaseException:
            os.close(printed_write)
            os.close(printed_read)
            raise
        os.close(printed_write)
        return child, printed_read

    def _rlimits(self) -> tuple[tuple[int, int], ...]:
        limits = self.limits
        return (
            (resource.RLIMIT_CPU, limits.cpu_seconds),
            (resource.RLIMIT_AS, limits.memory_bytes),
            (resource.RLIMIT_FSIZE, limits.file_bytes),
            (resource.RLIMIT_CORE, 0),
            (resource.RLIMIT_NOFILE, limits.open_files),
            (resource.RLIMIT_SIGPENDING, SIGNALS_PENDING),
            (resource.RLIMIT_NPROC, limits.processes),  # counted for the task's own uid
        )


def _link_or_copy(source: str, target: str) -> None:
    """A hard link where the tree shares the staged submission's file system (the grader's
    own private copy: the child can read it, never write it), else a copy."""
    try:
        os.link(source, target)
    except OSError:
        shutil.copy2(source, target)


def _confine_or_say(plan) -> None:
    """:func:`confine.confine_child`, saying why on the child's stderr if it fails."""
    try:
        confine.confine_child(plan)
    except BaseException as exc:
        os.write(2, f"{type(exc).__name__}: {exc}".encode(errors="replace"))
        raise

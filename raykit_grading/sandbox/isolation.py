"""What a submission's code can see, reach and outlive: the kernel's namespaces, through bubblewrap.

Every task runs in a sandbox made by bubblewrap (``bwrap``, Debian/Ubuntu package
``bubblewrap``), the tool Flatpak uses. It gives the child new namespaces:

* **mount**: a tree holding nothing but the Python it runs on (the interpreter and its standard
  library, with ``site-packages`` masked), numpy and Pillow (mounted at :data:`SITE`), the shared
  libraries those load, the task's own work folder (read-only, at :data:`WORK`), and its own
  ``tmp/`` folder, writable, at ``/tmp`` (measured against :attr:`Limits.disk` while the child
  runs, as in every sandbox kind). No other file of the machine exists in there: not the
  grader, not the reference raykit, not the hidden scenes, not a classmate's folder.
* **pid**: the child can name only its own processes, so it cannot signal or trace the grader
  or read another process's command line; when the task ends every process in it is killed.
  No ``/proc`` is mounted (as a normal user bwrap's init has the child's uid, and its
  ``/proc/1/mem`` would be writable).
* **network** (none but a loopback of its own), **ipc** and **uts**.

As root (Gradescope), bwrap needs no user namespace; the child's first act (in
:mod:`raykit_grading.inside.child`, before any submitted code is imported) is to drop to a uid of
its own for that one task, leased from :class:`UidPool` under a lock so that two graders on one
machine never share one. As a normal user, bwrap makes a user namespace (no privilege needed)
and the child stays the grader's uid, but inside the namespaces above.

Why bubblewrap: it is one small, well-kept setuid-free tool that works the same as root and as
a normal user, and its mount namespace both hides everything else and makes an interpreter under
``/root`` usable by the sandbox uid. Landlock would restrict reads as well, but leaves the network
(UDP) and the process tree to other means; ``unshare`` alone cannot build the minimal tree.
A seccomp filter (:func:`seccomp_filter`, given to bwrap) refuses the system calls that reach
kernel state namespaces do not isolate: the keyrings (``add_key``, ``request_key``, ``keyctl``;
a uid's keyring outlives its processes and would carry a hidden test's data to a later test or
student), and ``bpf``, ``perf_event_open``, ``userfaultfd``, ``io_uring_*``, module and kexec
loading; and any call of another architecture's numbering (32-bit or x32 calls on x86_64). It
also keeps a test to one process holding only what its limits and the grader's counts bound
(:mod:`raykit_grading.sandbox.budgets`): no second process, no socket, no ``O_TMPFILE``, no epoll,
inotify, fanotify or AIO, no record lock, no pipe enlarged.
The tree is mounted read-only but for ``/tmp``, so the child can fill no memory-backed folder.

If bwrap is missing or the kernel refuses namespaces, :func:`preflight` says so in one line and
the grader grades nothing (no score is written as if it had).
"""

from __future__ import annotations

import fcntl
import json
import os
import platform
import secrets
import shutil
import signal
import struct
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

SITE = "/sandbox/site"  # where numpy and Pillow appear in the sandbox
WORK = "/work"  # where the task's work folder appears, read-only
SANDBOX_UIDS = range(50000, 60000)  # the uids tasks run as, when grading as root
UID_LOCKS = Path("/run/raykit-grading/uids")
KILL_WAIT_SECONDS = 10.0  # for a killed task's processes to leave /proc
LIBRARIES = ("numpy", "PIL", "numpy.libs", "pillow.libs")
INSTALL_BWRAP = "install bubblewrap (Debian/Ubuntu: apt-get install bubblewrap)"


class IsolationUnavailable(RuntimeError):
    """The sandbox cannot be made here; the message says why and what to do, in one line."""


@dataclass(frozen=True)
class ChildPython:
    """The interpreter submissions run on, and exactly the files it needs.

    ``executable``: the real interpreter binary (a venv's python resolved to its base);
    ``stdlib``: its standard library folder; ``packages``: numpy's and Pillow's folders (and
    their bundled ``.libs``); ``shared_libraries``: every shared object these load, as
    ``(path the loader asks for, real file)``.
    """

    executable: str
    stdlib: str
    packages: tuple[str, ...]
    shared_libraries: tuple[tuple[str, str], ...]


_PROBE = """
import json, os, sys, sysconfig, numpy, PIL
print(json.dumps({
    "executable": os.path.realpath(sys.executable),
    "stdlib": sysconfig.get_paths()["stdlib"],
    "site": [os.path.dirname(os.path.dirname(m.__file__)) for m in (numpy, PIL)],
}))
"""


def probe_python(python: str) -> ChildPython:
    """Ask ``python`` (trusted: the instructor's) where it and its numpy and Pillow live."""
    try:
        run = subprocess.run(
            [python, "-I", "-c", _PROBE], capture_output=True, text=True, timeout=120
        )
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise IsolationUnavailable(f"cannot run the child Python {python}: {exc}") from None
    if run.returncode != 0:
        last = (run.stderr.strip().splitlines() or ["no output"])[-1]
        raise IsolationUnavailable(
            f"the child Python {python} cannot import numpy and Pillow ({last}); "
            "give --child-python one that can"
        )
    found = json.loads(run.stdout)
    packages = []
    for folder in dict.fromkeys(found["site"]):
        packages += [str(Path(folder) / n) for n in LIBRARIES if (Path(folder) / n).is_dir()]
    stdlib = found["stdlib"]
    binaries = [found["executable"]]
    for top in [*packages, str(Path(stdlib) / "lib-dynload")]:
        binaries += [str(p) for p in Path(top).rglob("*.so*") if p.is_file()]
    return ChildPython(
        found["executable"], stdlib, tuple(packages), _shared_libraries(binaries, packages)
    )


def _shared_libraries(binaries: list[str], packages: list[str]) -> tuple[tuple[str, str], ...]:
    """Every shared library ``binaries`` load, by ``ldd``: (path asked for, real file); the
    ones inside ``packages`` (numpy's bundled libraries) come with their package."""
    ldd = shutil.which("ldd")
    if ldd is None:
        raise IsolationUnavailable("ldd is not installed; the grader needs it to build sandboxes")
    found: dict[str, str] = {}
    for start in range(0, len(binaries), 64):
        run = subprocess.run(
            [ldd, *binaries[start : start + 64]], capture_output=True, text=True, timeout=120
        )
        for line in run.stdout.splitlines():
            words = line.split()
            path = words[2] if len(words) >= 3 and words[1] == "=>" else words[0] if words else ""
            inside_a_package = any(path.startswith(f"{p}/") for p in packages)
            if path.startswith("/") and os.path.exists(path) and not inside_a_package:
                # the folder as it really is (/lib may be a link to usr/lib), the name as asked
                asked = os.path.join(os.path.realpath(os.path.dirname(path)), Path(path).name)
                found[asked] = os.path.realpath(path)
    return tuple(sorted(found.items()))


# system calls refused in the sandbox, by architecture: (AUDIT_ARCH, {name: number}). Besides
# the kernel state above: tracing and reading other processes (ptrace, process_vm_*), making or
# entering namespaces and mounting, by the old calls or the new mount API (a chroot's way out),
# handles that bypass paths, and System V IPC and POSIX message queues: without an ipc
# namespace of its own (the chroot kind) a segment or queue outlives its test, open to every
# later test's uid (a hidden test's inputs, read by a visible one) and holding memory no
# process owns; and memfd_create, whose files hold memory the address-space limit does not
# count (each is cut at the file size limit, but there may be many). fallocate reserves disk
# without writing it, so that neither the file size limit nor a measure of blocks written
# keeps up with it (refused with EPERM, so the C library's posix_fallocate does not fall back
# to writing); statfs and fstatfs show the free space and inodes of a file system other tests
# share, a count another test's leftovers would change.
#
# And what would hold kernel memory that no limit of a process counts
# (raykit_grading.sandbox.budgets does the sum of what is left): sockets of every family (a socket's
# buffers hold up to 2 x net.core.wmem_max each, and a unix socket carries open files with no
# process holding them), a second process (fork and vfork; clone only as a thread, below), epoll and
# inotify instances (an epoll's watches multiply descriptors by descriptors), fanotify, and AIO
# contexts (io_setup).
SECCOMP_ARCHES = {
    "x86_64": (0xC000003E, {
        "add_key": 248, "request_key": 249, "keyctl": 250, "bpf": 321, "perf_event_open": 298,
        "userfaultfd": 323, "io_uring_setup": 425, "io_uring_enter": 426,
        "io_uring_register": 427, "init_module": 175, "finit_module": 313, "kexec_load": 246,
        "kexec_file_load": 320, "ptrace": 101, "process_vm_readv": 310,
        "process_vm_writev": 311, "unshare": 272, "setns": 308, "mount": 165, "umount2": 166,
        "pivot_root": 155, "chroot": 161, "name_to_handle_at": 303, "open_by_handle_at": 304,
        "open_tree": 428, "move_mount": 429, "fsopen": 430, "fsconfig": 431, "fsmount": 432,
        "fspick": 433, "mount_setattr": 442,
        "shmget": 29, "shmat": 30, "shmctl": 31, "shmdt": 67, "semget": 64, "semop": 65,
        "semctl": 66, "semtimedop": 220, "msgget": 68, "msgsnd": 69, "msgrcv": 70,
        "msgctl": 71, "mq_open": 240, "mq_unlink": 241, "mq_timedsend": 242,
        "mq_timedreceive": 243, "mq_notify": 244, "mq_getsetattr": 245,
        "memfd_create": 319, "memfd_secret": 447,
        "fallocate": 285, "statfs": 137, "fstatfs": 138,
        "socket": 41, "socketpair": 53, "fork": 57, "vfork": 58, "epoll_create": 213,
        "epoll_create1": 291, "inotify_init": 253, "inotify_init1": 294, "fanotify_init": 300,
        "io_setup": 206,
    }),
    "aarch64": (0xC00000B7, {
        "add_key": 217, "request_key": 218, "keyctl": 219, "bpf": 280, "perf_event_open": 241,
        "userfaultfd": 282, "io_uring_setup": 425, "io_uring_enter": 426,
        "io_uring_register": 427, "init_module": 105, "finit_module": 273, "kexec_load": 104,
        "kexec_file_load": 294, "ptrace": 117, "process_vm_readv": 270,
        "process_vm_writev": 271, "unshare": 97, "setns": 268, "mount": 40, "umount2": 39,
        "pivot_root": 41, "chroot": 51, "name_to_handle_at": 264, "open_by_handle_at": 265,
        "open_tree": 428, "move_mount": 429, "fsopen": 430, "fsconfig": 431, "fsmount": 432,
        "fspick": 433, "mount_setattr": 442,
        "shmget": 194, "shmat": 196, "shmctl": 195, "shmdt": 197, "semget": 190, "semop": 193,
        "semctl": 191, "semtimedop": 192, "msgget": 186, "msgsnd": 189, "msgrcv": 188,
        "msgctl": 187, "mq_open": 180, "mq_unlink": 181, "mq_timedsend": 182,
        "mq_timedreceive": 183, "mq_notify": 184, "mq_getsetattr": 185,
        "memfd_create": 279, "memfd_secret": 447,
        "fallocate": 47, "statfs": 43, "fstatfs": 44,
        "socket": 198, "socketpair": 199, "epoll_create1": 20, "inotify_init1": 26,
        "fanotify_init": 262, "io_setup": 0,
    }),
}  # fmt: skip
# clone(2) only makes a thread of the test's one process: its memory, its open files and its
# signal handlers shared (CLONE_VM|CLONE_FILES|CLONE_SIGHAND|CLONE_THREAD), no CLONE_VFORK (a
# vfork child execs into a process of its own) and no CLONE_NEW* flag (a user namespace is
# root in a world of its own: mounts through the new mount API, a tmpfs outside every limit);
# a test is then one process, whose limits bound all it holds. clone3(2) hides its flags in
# memory seccomp cannot read, so it fails with ENOSYS and the C library falls back to clone,
# as under Docker's own profile; so does openat2(2), whose flags are in memory as well.
CLONE_CALLS = {"x86_64": (56, 435), "aarch64": (220, 435)}  # clone, clone3
CLONE_NEW_FLAGS = 0x7E020000  # CLONE_NEWNS|NEWCGROUP|NEWUTS|NEWIPC|NEWUSER|NEWPID|NEWNET
CLONE_VM, CLONE_FILES, CLONE_SIGHAND, CLONE_VFORK, CLONE_THREAD = (
    0x100, 0x400, 0x800, 0x4000, 0x10000,
)  # fmt: skip
THREAD_FLAGS = CLONE_VM | CLONE_FILES | CLONE_SIGHAND | CLONE_THREAD
CLONE_CHECKED = THREAD_FLAGS | CLONE_VFORK | CLONE_NEW_FLAGS
# a file opened with O_TMPFILE has no name the disk budget's walk can find (refused with
# EOPNOTSUPP, as where a file system cannot make one: Python's tempfile then makes a named
# file and unlinks it, which the budget counts through the descriptor); a pipe is not
# enlarged past its 16 pages (F_SETPIPE_SZ refused), and no POSIX record lock is taken (each
# costs the kernel a record, and a test could take 100,000s; flock's one lock an open file
# is left)
OPEN_CALLS = {"x86_64": {"open": (2, 24), "openat": (257, 32)}, "aarch64": {"openat": (56, 32)}}
OPENAT2 = 437  # how: a struct in memory; ENOSYS, and the C library never needs it
O_TMPFILE_BIT = 0o20000000  # __O_TMPFILE, the same on x86_64 and aarch64
FCNTL_CALL = {"x86_64": 72, "aarch64": 25}
FCNTL_REFUSED = {"F_SETLK": 6, "F_SETLKW": 7, "F_OFD_SETLK": 37, "F_OFD_SETLKW": 38,
                 "F_SETPIPE_SZ": 1031}  # fmt: skip
X32_SYSCALL_BIT = 0x40000000
SECCOMP_RET_ALLOW, SECCOMP_RET_ERRNO, EPERM, ENOSYS, EOPNOTSUPP = 0x7FFF0000, 0x50000, 1, 38, 95


def bpf_program(steps: list[tuple]) -> bytes:
    """Classic BPF from ``steps``: ``("label", name)`` marks a place; ``("ld", offset)`` loads
    a word of seccomp_data; ``("and", k)`` masks it; ``("jeq"|"jge"|"jset", k, where_true,
    where_false)`` jumps to labels (None: the next step); ``("ret", value)``. Jumps go forward
    only, as BPF requires."""
    places, index = {}, 0
    for step in steps:
        if step[0] == "label":
            places[step[1]] = index
        else:
            index += 1
    program, index = [], 0
    for step in steps:
        if step[0] == "label":
            continue
        if step[0] == "ld":
            program.append(struct.pack("HBBI", 0x20, 0, 0, step[1]))
        elif step[0] == "and":
            program.append(struct.pack("HBBI", 0x54, 0, 0, step[1]))
        elif step[0] == "ret":
            program.append(struct.pack("HBBI", 0x06, 0, 0, step[1]))
        else:
            code = {"jeq": 0x15, "jge": 0x35, "jset": 0x45}[step[0]]
            jumps = [0 if w is None else places[w] - index - 1 for w in step[2:4]]
            if not all(0 <= j < 256 for j in jumps):
                raise ValueError(f"a jump out of reach in step {step}")
            program.append(struct.pack("HBBI", code, jumps[0], jumps[1], step[1]))
        index += 1
    return b"".join(program)


def seccomp_filter(machine: str | None = None) -> bytes:
    """The sandbox's seccomp program, classic BPF as bwrap's ``--seccomp`` and
    ``PR_SET_SECCOMP`` read it: a call of another architecture, an x32 call, one of
    :data:`SECCOMP_ARCHES` (every socket, a second process, the kernel state above), a
    ``clone`` that is not a thread (:data:`THREAD_FLAGS`) or an ``fcntl`` that enlarges a pipe
    or takes a record lock (:data:`FCNTL_REFUSED`) fails with EPERM; an ``open`` with
    ``O_TMPFILE`` with EOPNOTSUPP; ``clone3`` and ``openat2`` with ENOSYS; everything else is
    allowed."""
    machine = machine or platform.machine()
    if machine not in SECCOMP_ARCHES:
        raise IsolationUnavailable(f"no seccomp filter for {machine} machines; grade on x86_64")
    arch, calls = SECCOMP_ARCHES[machine]
    clone, clone3 = CLONE_CALLS[machine]
    opens = OPEN_CALLS[machine]
    steps: list[tuple] = [("ld", 4), ("jeq", arch, None, "deny"), ("ld", 0)]
    steps += [("jge", X32_SYSCALL_BIT, "deny", None), ("jeq", clone, "clone", None)]
    steps += [("jeq", clone3, "enosys", None), ("jeq", OPENAT2, "enosys", None)]
    steps += [("jeq", number, name, None) for name, (number, _) in opens.items()]
    steps += [("jeq", FCNTL_CALL[machine], "fcntl", None)]
    steps += [("jeq", number, "deny", None) for number in sorted(calls.values())]
    steps += [("ret", SECCOMP_RET_ALLOW)]
    steps += [("label", "clone"), ("ld", 16), ("and", CLONE_CHECKED)]  # args[0]: its flags
    steps += [("jeq", THREAD_FLAGS, "allow", "deny")]
    for name, (_, flags) in opens.items():  # the flags' low word: args[1] of open, [2] of openat
        steps += [("label", name), ("ld", flags), ("jset", O_TMPFILE_BIT, "eopnotsupp", "allow")]
    steps += [("label", "fcntl"), ("ld", 24)]  # args[1]: the command
    steps += [("jeq", command, "deny", None) for command in FCNTL_REFUSED.values()]
    steps += [("ret", SECCOMP_RET_ALLOW)]
    steps += [("label", "allow"), ("ret", SECCOMP_RET_ALLOW)]
    steps += [("label", "deny"), ("ret", SECCOMP_RET_ERRNO | EPERM)]
    steps += [("label", "enosys"), ("ret", SECCOMP_RET_ERRNO | ENOSYS)]
    steps += [("label", "eopnotsupp"), ("ret", SECCOMP_RET_ERRNO | EOPNOTSUPP)]
    return bpf_program(steps)


def find_bwrap() -> str:
    bwrap = shutil.which("bwrap") or next(
        (p for p in ("/usr/bin/bwrap", "/usr/local/bin/bwrap") if os.access(p, os.X_OK)), None
    )
    if bwrap is None:
        raise IsolationUnavailable(
            f"cannot isolate submissions: bubblewrap (bwrap) is not installed; {INSTALL_BWRAP}"
        )
    return bwrap


def _parents(path: str) -> list[str]:
    parts = Path(path).parts[1:-1]
    return ["/" + "/".join(parts[: i + 1]) for i in range(len(parts))]


def sandbox_arguments(
    python: ChildPython, work: Path, submission: Path, as_root: bool
) -> list[str]:
    """bwrap's arguments (without the command) for one task: the tree described above."""
    arguments = ["--unshare-ipc", "--unshare-pid", "--unshare-net", "--unshare-uts"]
    arguments += ["--unshare-cgroup-try", "--die-with-parent", "--new-session", "--clearenv"]
    if not as_root:  # a user namespace needs no privilege, and none may be made inside it
        arguments += ["--unshare-user", "--disable-userns"]
    made: set[str] = set()

    def bind(source: str, target: str) -> None:
        for parent in _parents(target):
            if parent not in made:
                made.add(parent)
                arguments.extend(["--perms", "0755", "--dir", parent])
        arguments.extend(["--ro-bind", source, target])
        made.add(target)

    bind(python.executable, python.executable)
    bind(python.stdlib, python.stdlib)
    for hidden in ("site-packages", "dist-packages"):
        if (Path(python.stdlib) / hidden).is_dir():
            arguments += ["--tmpfs", str(Path(python.stdlib) / hidden)]
    for package in python.packages:
        bind(package, f"{SITE}/{Path(package).name}")
    for asked, real in python.shared_libraries:
        if asked not in made:
            bind(real, asked)
    for link in ("/lib", "/lib64", "/bin"):  # the loader's own path names them
        if os.path.islink(link):
            arguments += ["--symlink", os.readlink(link), link]
    if os.path.isfile("/etc/ld.so.cache"):
        bind("/etc/ld.so.cache", "/etc/ld.so.cache")
    bind(str(work), WORK)
    bind(str(submission), f"{WORK}/submission")
    # no /proc: as a normal user, bwrap's own init (pid 1 in the sandbox) is the child's uid,
    # and /proc/1/mem would let the child write its code (leave the process group, drop
    # --die-with-parent, outlive the test); nothing the child runs needs /proc
    arguments += ["--dev", "/dev", "--remount-ro", "/dev"]
    arguments += ["--bind", str(work / "tmp"), "/tmp", "--chdir", "/tmp"]
    arguments += ["--remount-ro", "/"]  # nothing but /tmp (of a fixed size) can be written
    for name, value in child_environment("/tmp").items():
        arguments += ["--setenv", name, value]
    return arguments


def child_environment(tmp: str) -> dict[str, str]:
    """The child's whole environment: ``tmp`` its home and scratch folder, one BLAS thread."""
    return {
        "HOME": tmp,
        "TMPDIR": tmp,
        "PATH": "/usr/bin:/bin",
        "OPENBLAS_NUM_THREADS": "1",
        "OMP_NUM_THREADS": "1",
        "MKL_NUM_THREADS": "1",
        "LANG": "C.UTF-8",
    }


class UidLease:
    """One sandbox uid, held (by an flock) for one task; see :class:`UidPool`."""

    def __init__(self, uid: int, lock_fd: int) -> None:
        self.uid = uid
        self._lock_fd = lock_fd

    def release(self) -> None:
        """Kill whatever still runs as the uid, then give it back."""
        kill_uid(self.uid)
        os.close(self._lock_fd)  # closing drops the flock


class UidPool:
    """Unprivileged uids for tasks, when grading as root: one per task at a time, never shared.

    A uid is taken by an exclusive, non-blocking ``flock`` on ``UID_LOCKS/<uid>``, held until
    the task's processes are all dead: two graders on one machine (or a batch's parallel
    graders) never run tasks as the same uid. A uid that still has processes when its lock is
    free was left by a grader that was killed: they are killed before the uid is used again.
    """

    def __init__(self, uids: range = SANDBOX_UIDS, locks: Path = UID_LOCKS) -> None:
        self.uids = uids
        self.locks = locks
        try:
            locks.mkdir(parents=True, exist_ok=True, mode=0o700)
            info = os.lstat(locks)
        except OSError as exc:
            raise IsolationUnavailable(f"cannot make the uid lock folder {locks}: {exc}") from None
        if info.st_uid != 0 or info.st_mode & 0o022 or os.path.islink(locks):
            raise IsolationUnavailable(f"{locks} must be a folder only root may write")

    def lease(self) -> UidLease:
        start = secrets.randbelow(len(self.uids))  # a test seldom gets the uid of the one before
        for step in range(len(self.uids)):
            uid = self.uids[(start + step) % len(self.uids)]
            fd = os.open(self.locks / str(uid), os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o600)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                continue
            kill_uid(uid)  # a killed grader's leftovers
            return UidLease(uid, fd)
        raise IsolationUnavailable(f"all {len(self.uids)} sandbox uids are in use")


def kill_as(uid: int) -> None:
    """SIGKILL every process of ``uid`` at once: ``kill(-1)`` from a process of that uid
    (the kernel signals all it may in one pass, so a fork bomb cannot outrun it)."""
    pid = os.fork()
    if pid == 0:
        try:
            os.setgroups([])
            os.setresgid(uid, uid, uid)
            os.setresuid(uid, uid, uid)
            os.kill(-1, signal.SIGKILL)  # every process of the uid but this one
        finally:
            os._exit(0)
    os.waitpid(pid, 0)


def kill_uid(uid: int) -> None:
    """SIGKILL every process of ``uid`` (as root): all at once, then sweeping /proc until
    none is left. A killed process stays in /proc until it has given back its memory and its
    parent has reaped it, so the sweeps wait for that, a little longer each time, up to
    :data:`KILL_WAIT_SECONDS`; a uid whose processes outlast that is reported (the next lease
    of the uid kills them again), so its lock is never given back in silence."""
    kill_as(uid)
    pause, deadline = 0.001, time.monotonic() + KILL_WAIT_SECONDS
    while True:
        found = []
        for proc in Path("/proc").iterdir():
            if not proc.name.isdigit():
                continue
            try:
                if proc.stat().st_uid == uid:
                    found.append(proc.name)
                    os.kill(int(proc.name), signal.SIGKILL)
            except (FileNotFoundError, ProcessLookupError, PermissionError):
                pass
        if not found:
            return
        if time.monotonic() > deadline:
            print(f"raykit_grading: sandbox uid {uid} still has processes {found} "
                  f"{KILL_WAIT_SECONDS:.0f} s after SIGKILL", file=sys.stderr)  # fmt: skip
            return
        time.sleep(pause)
        pause = min(2 * pause, 0.05)

"""Confinement without namespaces: a chroot tree, a uid of its own, Landlock and seccomp.

Docker's default confinement (Gradescope runs ``run_autograder`` as root inside it) keeps 14
capabilities (no ``CAP_SYS_ADMIN``) and a seccomp profile that refuses ``unshare``, ``setns``,
``mount`` and ``clone`` with a ``CLONE_NEW*`` flag: no namespace can be made, so bubblewrap
fails. What that confinement leaves root is enough for a sandbox of another kind, which each
test's child makes for itself between ``fork`` and ``exec`` (:func:`confine_child`, in order):

1. its own session, the limits (:class:`raykit_grading.sandbox.base.Limits`), and
   ``oom_score_adj`` 1000, so that if the container's memory runs out the kernel kills the
   child, never the grader;
2. ``chroot`` into a minimal tree (:func:`chroot_tree`: the interpreter, its standard library
   without ``site-packages``, numpy and Pillow at :data:`raykit_grading.sandbox.isolation.SITE`, the
   shared libraries they load, made once, root-owned and read-only) and ``chdir`` into the
   test's own folder in it (a slot, ``/tasks/<n>``, mode 750 root:its gid, holding the child
   script, the inputs, a copy of the submission, and ``tmp/`` of its uid, mode 700);
3. the test's own uid and gid, leased (``setgroups([])``, ``setgid``, ``setuid``: a process
   that leaves uid 0 this way keeps no capability), then ``PR_SET_NO_NEW_PRIVS``;
4. Landlock where the kernel has it (:func:`landlock_restrict`): read and execute the tree,
   read its own folder, write only its ``tmp/`` (and ``/dev/null``); from ABI 6 also no
   signal to, and no abstract unix socket of, any process outside its domain;
5. the seccomp filter of :func:`raykit_grading.sandbox.isolation.seccomp_filter` (no socket, no
   second process, no keyrings, System V IPC, ptrace, bpf, namespaces, mounts...);

then ``exec`` of the child Python. After the test every process of its uid is killed
(:func:`raykit_grading.sandbox.isolation.kill_uid`) before the uid is leased again.

The tree is built where only root can reach it (:data:`TREES`), once per interpreter and set
of packages: Gradescope's ``setup.sh`` builds it when the image is made; elsewhere the first
grading builds it. Bind mounts need a mount namespace, so its files are copies.

**Slots.** A test sees its own folder and, by ``..``, the folder that holds it, which ``stat``
shows whatever Landlock says (its link count, its times). So the test folders are a fixed set
of :data:`SLOTS` folders made with the tree and never made or removed afterwards: ``/tasks``
looks the same whether other tests ran, run now or left anything. A test leases a slot
(:func:`lease_slot`, an ``flock`` outside the tree), which is emptied before it is filled (what
a killed grader left, too) and after the test; only what is inside a slot changes, and that is
the test's own.
"""

from __future__ import annotations

import ctypes
import fcntl
import hashlib
import json
import os
import shutil
import stat
import struct
from dataclasses import dataclass, field
from pathlib import Path

from raykit_grading.sandbox.isolation import SITE, ChildPython, IsolationUnavailable
from raykit_grading.sandbox.leftovers import remove_tree

TREES = Path("/var/cache/raykit-grading")  # root only (mode 700)
TREE_LAYOUT = 3  # raise when what goes into a tree changes: old trees are then not used
LEFT_OUT = {"site-packages", "dist-packages", "test", "idlelib", "tkinter", "turtledemo",
            "ensurepip", "lib2to3", "pydoc_data"}  # fmt: skip
TASKS = "tasks"  # the tree's folder of test folders (mode 711: entered, never listed)
SLOTS = 32  # test folders in it, made with the tree: more than graders run at once on a machine
QUARANTINE = "quarantine"  # beside the trees: what could not be removed, moved aside
DEVICES_WRITTEN = ("/dev/null",)  # what code may write beside its tmp/ (os.devnull, as anywhere)

_libc = ctypes.CDLL(None, use_errno=True)
_libc.syscall.restype = ctypes.c_long
PR_SET_NO_NEW_PRIVS, PR_SET_SECCOMP, SECCOMP_MODE_FILTER = 38, 22, 2
LANDLOCK_CREATE_RULESET, LANDLOCK_ADD_RULE, LANDLOCK_RESTRICT_SELF = 444, 445, 446
LANDLOCK_CREATE_RULESET_VERSION, LANDLOCK_RULE_PATH_BENEATH = 1, 1
FS_EXECUTE, FS_WRITE_FILE, FS_READ_FILE, FS_READ_DIR = 1 << 0, 1 << 1, 1 << 2, 1 << 3
FS_MAKE_EVERYTHING = sum(1 << bit for bit in range(4, 13))  # remove and make every kind
FS_REFER, FS_TRUNCATE, FS_IOCTL_DEV = 1 << 13, 1 << 14, 1 << 15
NET_BIND_TCP, NET_CONNECT_TCP = 1 << 0, 1 << 1
SCOPE_ABSTRACT_UNIX_SOCKET, SCOPE_SIGNAL = 1 << 0, 1 << 1


def _check(result: int, what: str) -> int:
    if result < 0:
        number = ctypes.get_errno()
        raise OSError(number, f"{what}: {os.strerror(number)}")
    return result


def landlock_abi() -> int:
    """The kernel's Landlock ABI version; 0 if it has none (or it is switched off)."""
    return max(0, _libc.syscall(LANDLOCK_CREATE_RULESET, None, 0, LANDLOCK_CREATE_RULESET_VERSION))


def landlock_restrict(
    abi: int, read_execute: list[str], read: list[str], read_write: list[str]
) -> None:
    """Restrict this process (and what it starts) to these paths, as far as ABI ``abi`` goes:
    ``read_execute`` folders or files may be read and run, ``read`` read, ``read_write``
    changed; nothing else. From ABI 4 no TCP either, from ABI 6 signals and abstract unix
    sockets reach only processes in the same domain. Needs NO_NEW_PRIVS set first."""
    fs = FS_EXECUTE | FS_WRITE_FILE | FS_READ_FILE | FS_READ_DIR | FS_MAKE_EVERYTHING
    fs |= (FS_REFER if abi >= 2 else 0) | (FS_TRUNCATE if abi >= 3 else 0)
    fs |= FS_IOCTL_DEV if abi >= 5 else 0
    net = NET_BIND_TCP | NET_CONNECT_TCP if abi >= 4 else 0
    scoped = SCOPE_ABSTRACT_UNIX_SOCKET | SCOPE_SIGNAL if abi >= 6 else 0
    attr = struct.pack("QQQ", fs, net, scoped)
    size = 24 if abi >= 6 else 16 if abi >= 4 else 8
    ruleset = _check(
        _libc.syscall(LANDLOCK_CREATE_RULESET, attr[:size], size, 0), "landlock_create_ruleset"
    )
    reading = FS_READ_FILE | FS_READ_DIR
    writing = fs & ~FS_EXECUTE
    try:
        for paths, allowed in ((read_execute, reading | FS_EXECUTE), (read, reading),
                               (read_write, writing)):  # fmt: skip
            for path in paths:
                fd = os.open(path, os.O_PATH | os.O_CLOEXEC)
                try:
                    is_dir = stat.S_ISDIR(os.fstat(fd).st_mode)
                    rights = (
                        allowed
                        if is_dir
                        else allowed & (FS_EXECUTE | FS_READ_FILE | FS_WRITE_FILE | FS_TRUNCATE)
                    )
                    rule = struct.pack("=Qi", rights, fd)
                    _check(
                        _libc.syscall(LANDLOCK_ADD_RULE, ruleset, LANDLOCK_RULE_PATH_BENEATH,
                                      rule, 0),
                        f"landlock_add_rule {path}",
                    )  # fmt: skip
                finally:
                    os.close(fd)
        _check(_libc.syscall(LANDLOCK_RESTRICT_SELF, ruleset, 0), "landlock_restrict_self")
    finally:
        os.close(ruleset)


class _SockFprog(ctypes.Structure):
    _fields_ = [("len", ctypes.c_ushort), ("filter", ctypes.c_void_p)]


def install_seccomp(program: bytes) -> None:
    """Install a classic BPF seccomp program on this process (NO_NEW_PRIVS or CAP_SYS_ADMIN
    first); it stays through exec and is inherited by every child."""
    buffer = ctypes.create_string_buffer(program, len(program))
    prog = _SockFprog(len(program) // 8, ctypes.cast(buffer, ctypes.c_void_p))
    _check(
        _libc.prctl(PR_SET_SECCOMP, SECCOMP_MODE_FILTER, ctypes.byref(prog), 0, 0),
        "prctl(PR_SET_SECCOMP)",
    )


def no_new_privileges() -> None:
    _check(_libc.prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0), "prctl(PR_SET_NO_NEW_PRIVS)")


# ---- the container's own memory and CPU -------------------------------------------------


@dataclass(frozen=True)
class ContainerLimits:
    """What the grader's cgroup gives it: ``memory_bytes`` (None: no limit found) and
    ``cpus`` (the CPU quota in CPUs, None: none). ``memory_cgroup``: the folder of the cgroup
    whose limit that is, where the grader reads what the container holds and how often its
    OOM killer fired (:class:`raykit_grading.sandbox.budgets.ContainerMemory`); ``cgroup_v2`` says
    which files it has."""

    memory_bytes: int | None
    cpus: float | None
    memory_cgroup: Path | None = field(default=None, compare=False)
    cgroup_v2: bool = field(default=False, compare=False)


UNLIMITED = 1 << 60  # cgroup v1 says "no limit" as a huge number


def _cgroup_folders(controller: str, proc: Path = Path("/proc/self")) -> list[Path]:
    """This process's cgroup folder for ``controller`` ("" for cgroup v2) and its parents up
    to the hierarchy's mount, as mounted here (from /proc/self/cgroup and mountinfo)."""
    paths = {}
    for line in (proc / "cgroup").read_text().splitlines():
        number, controllers, path = line.split(":", 2)
        for name in controllers.split(",") if controllers else [""]:
            paths[name] = path
    if controller not in paths:
        return []
    found = []
    for line in (proc / "mountinfo").read_text().splitlines():
        before, _, after = line.partition(" - ")
        fields, kind = before.split(), after.split()
        if not kind or kind[0] not in ("cgroup", "cgroup2"):
            continue
        options = set(kind[2].split(",")) if len(kind) > 2 else set()
        wanted_v2 = controller == ""
        if wanted_v2 != (kind[0] == "cgroup2") or (controller and controller not in options):
            continue
        root, mountpoint = fields[3], Path(fields[4])
        path = paths[controller]
        relative = path[len(root) :] if path.startswith(root) else ""
        folder = mountpoint / relative.strip("/") if relative.strip("/") else mountpoint
        if not folder.is_dir():
            folder = mountpoint  # a cgroup namespace shows the container's own as the root
        while True:
            found.append(folder)
            if folder == mountpoint:
                break
            folder = folder.parent
        break
    return found


def _read_number(path: Path) -> int | None:
    try:
        text = path.read_text().split()
    except OSError:
        return None
    if not text or text[0] == "max":
        return None
    value = int(text[0])
    return None if value >= UNLIMITED else value


def container_limits(proc: Path = Path("/proc/self")) -> ContainerLimits:
    """The tightest memory limit and CPU quota over the grader's cgroup and its parents."""
    memory, cpus = [], []  # memory: (limit, its folder, cgroup v2)
    for folder in _cgroup_folders("", proc):
        memory.append((_read_number(folder / "memory.max"), folder, True))
        try:
            quota, period = (folder / "cpu.max").read_text().split()
            if quota != "max":
                cpus.append(int(quota) / int(period))
        except (OSError, ValueError):
            pass
    for folder in _cgroup_folders("memory", proc):
        memory.append((_read_number(folder / "memory.limit_in_bytes"), folder, False))
    for folder in _cgroup_folders("cpu", proc):
        quota = _read_number(folder / "cpu.cfs_quota_us")
        period = _read_number(folder / "cpu.cfs_period_us")
        if quota is not None and quota > 0 and period:
            cpus.append(quota / period)
    memory = [m for m in memory if m[0]]
    tightest = min(memory, key=lambda m: m[0]) if memory else (None, None, False)
    return ContainerLimits(tightest[0], min(cpus) if cpus else None, *tightest[1:])


# ---- the chroot tree --------------------------------------------------------------------


def _tree_key(python: ChildPython) -> str:
    """What the tree is made from: paths, and files that change when they are upgraded (not
    folders, whose times change whenever a ``__pycache__`` is written)."""
    described = [TREE_LAYOUT, python.executable, python.stdlib, python.packages]
    markers = [python.executable, f"{python.stdlib}/os.py"]
    markers += [f"{p}/__init__.py" for p in python.packages if Path(p, "__init__.py").exists()]
    for path in markers:
        info = os.stat(path)
        described.append([path, info.st_mtime_ns, info.st_size])
    described.append(python.shared_libraries)
    return hashlib.sha256(json.dumps(described).encode()).hexdigest()[:20]


def _root_only_folder(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True, mode=0o700)
    info = os.lstat(folder)
    if info.st_uid != 0 or info.st_mode & 0o077 or stat.S_ISLNK(info.st_mode):
        raise IsolationUnavailable(f"{folder} must be a folder only root may enter (mode 700)")


def chroot_tree(python: ChildPython, trees: Path = TREES) -> Path:
    """The minimal tree for ``python``, built now if it is not there yet (as root)."""
    try:
        _root_only_folder(trees)
        tree = trees / f"tree-{_tree_key(python)}"
        if tree.is_dir():
            return tree
        with open(trees / ".lock", "w") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)  # one builder at a time; the others then use it
            if not tree.is_dir():
                building = trees / f".building-{os.getpid()}"
                shutil.rmtree(building, ignore_errors=True)
                _build_tree(python, building)
                os.rename(building, tree)
        return tree
    except OSError as exc:
        raise IsolationUnavailable(f"cannot build the sandbox tree in {trees}: {exc}") from None


def _build_tree(python: ChildPython, tree: Path) -> None:
    def place(source: str, target: str) -> None:
        destination = tree / target.lstrip("/")
        destination.parent.mkdir(parents=True, exist_ok=True, mode=0o755)
        if os.path.isdir(source):
            shutil.copytree(
                source, destination, symlinks=True, dirs_exist_ok=True,
                ignore=lambda folder, names: [n for n in names if n in LEFT_OUT]
                if folder == source else [],
            )  # fmt: skip
        else:
            shutil.copy2(source, destination)

    tree.mkdir(mode=0o755)
    place(python.executable, python.executable)
    place(python.stdlib, python.stdlib)
    for package in python.packages:
        place(package, f"{SITE}/{Path(package).name}")
    for asked, real in python.shared_libraries:
        if not (tree / asked.lstrip("/")).exists():
            place(real, asked)
    for link in ("/lib", "/lib64", "/bin"):  # the loader's own path names them
        if os.path.islink(link) and not (tree / link[1:]).exists():
            os.symlink(os.readlink(link), tree / link[1:])
    if os.path.isfile("/etc/ld.so.cache"):
        place("/etc/ld.so.cache", "/etc/ld.so.cache")
    (tree / "dev").mkdir(mode=0o755)
    for name, (major, minor) in {"null": (1, 3), "zero": (1, 5), "urandom": (1, 9)}.items():
        try:  # CAP_MKNOD is in Docker's default set; without it there is no /dev/null
            os.mknod(tree / "dev" / name, 0o666 | stat.S_IFCHR, os.makedev(major, minor))
        except OSError:
            pass
    (tree / TASKS).mkdir(mode=0o711)
    for slot in range(SLOTS):
        (tree / TASKS / str(slot)).mkdir(mode=0o700)
    for folder, dirs, files in os.walk(tree):
        for name in dirs + files:
            path = Path(folder) / name
            if path.is_symlink():
                continue
            info = path.lstat()
            os.chown(path, 0, 0)
            if stat.S_ISDIR(info.st_mode) and Path(folder) == tree / TASKS:
                os.chmod(path, 0o700)  # a slot: its test's gid is given it while it runs
            elif stat.S_ISDIR(info.st_mode):
                os.chmod(path, 0o711 if name == TASKS and folder == str(tree) else 0o755)
            elif stat.S_ISREG(info.st_mode):  # readable by all, writable by none but root
                os.chmod(path, 0o755 if info.st_mode & 0o111 else 0o644)
            elif stat.S_ISCHR(info.st_mode):  # /dev/null as everywhere (mknod took the umask)
                os.chmod(path, 0o666)
    os.chown(tree, 0, 0)
    os.chmod(tree, 0o755)


def top_entries(tree: Path) -> list[str]:
    """What the child may read and run in the tree: every top folder but the test folders."""
    return sorted(f"/{e.name}" for e in tree.iterdir() if e.name != TASKS and e.exists())


class SlotLease:
    """One of the tree's test folders, held (by an ``flock``) for one test; see
    :func:`lease_slot`. ``outside`` is its path here, ``inside`` as the child sees it."""

    def __init__(self, tree: Path, number: int, lock_fd: int) -> None:
        self.outside = tree / TASKS / str(number)
        self.inside = f"/{TASKS}/{number}"
        self._lock_fd = lock_fd

    def empty(self) -> list[str]:
        """Remove everything in the slot (never raises): what could not be removed is moved
        into the quarantine and named in the list returned."""
        problems = []
        try:
            names = os.listdir(self.outside)
        except OSError as exc:
            return [f"cannot list {self.outside}: {exc.strerror}"]
        for name in names:
            removal = remove_tree(self.outside / name, self.outside.parents[2] / QUARANTINE)
            if removal.problem:
                problems.append(removal.problem)
        try:
            os.chown(self.outside, 0, 0)
            os.chmod(self.outside, 0o700)
        except OSError as exc:
            problems.append(f"cannot close {self.outside}: {exc.strerror}")
        return problems

    def release(self) -> None:
        os.close(self._lock_fd)


def lease_slot(tree: Path) -> tuple[SlotLease, list[str]]:
    """A free slot of ``tree``, emptied: (the lease, what could not be removed from it)."""
    locks = tree.parent / f".slots-{tree.name}"
    _root_only_folder(locks)
    for number in range(SLOTS):
        fd = os.open(locks / str(number), os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            continue
        lease = SlotLease(tree, number, fd)
        return lease, lease.empty()
    raise IsolationUnavailable(f"all {SLOTS} test folders of {tree} are in use")


@dataclass(frozen=True)
class ChildConfinement:
    """Everything :func:`confine_child` needs, computed before the fork."""

    tree: str
    folder: str  # the test's folder, as seen inside the tree
    uid: int
    rlimits: tuple[tuple[int, int], ...]  # (resource, value)
    landlock_abi: int
    landlock_read_execute: tuple[str, ...]
    seccomp: bytes


def confine_child(plan: ChildConfinement) -> None:
    """In the forked child, as root, before exec: the steps of this module's docstring. Any
    failure raises, and the child is never run."""
    import resource

    os.setsid()
    try:
        with open("/proc/self/oom_score_adj", "w") as adj:
            adj.write("1000")
    except OSError:
        pass
    for which, value in plan.rlimits:
        resource.setrlimit(which, (value, value))
    os.chroot(plan.tree)
    os.chdir(plan.folder)
    os.setgroups([])
    os.setresgid(plan.uid, plan.uid, plan.uid)
    os.setresuid(plan.uid, plan.uid, plan.uid)
    if 0 in os.getresuid() or 0 in os.getresgid():
        raise OSError("could not leave root")
    no_new_privileges()
    if plan.landlock_abi:
        landlock_restrict(
            plan.landlock_abi,
            list(plan.landlock_read_execute),
            [plan.folder],
            [f"{plan.folder}/tmp", *DEVICES_WRITTEN],
        )
    install_seccomp(plan.seccomp)


def main() -> None:
    """``python -m raykit_grading.sandbox.confine``: build the tree for this Python now (as root;
    Gradescope's ``setup.sh`` does, so that no grading pays for it)."""
    import sys

    from raykit_grading.sandbox.isolation import probe_python

    try:
        print(f"sandbox tree: {chroot_tree(probe_python(sys.executable))}")
    except IsolationUnavailable as exc:
        print(f"raykit_grading: error: {exc}", file=sys.stderr)
        sys.exit(3)


if __name__ == "__main__":
    main()

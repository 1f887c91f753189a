"""Every resource a test can hold while it runs: counted against a budget, or refused.

A test's code runs in one process (:mod:`raykit_grading.sandbox.base`). What it could hold is either
refused by the sandbox's seccomp filter (:func:`raykit_grading.sandbox.isolation.seccomp_filter`),
bounded by a limit of that process, or counted by the grader while it runs (:class:`Watch`,
every :data:`WATCH_SECONDS`): a test whose count passes its budget is stopped and scores 0,
told which budget it passed. This is the arithmetic, in one place.

**Processes and descriptors.** One process: ``fork``, ``vfork`` and a ``clone`` that is not a
thread are refused; a thread shares the process's memory, descriptors and signal handlers
(``clone`` must carry ``CLONE_VM|CLONE_FILES|CLONE_SIGHAND|CLONE_THREAD``; ``unshare``, which
could part them, is refused). So a test holds at most ``Limits.open_files`` (64) descriptors
and ``Limits.processes`` (16) threads, whatever it does, and everything it holds is its one
process's.

**Memory.** Where the grader runs in a container of L bytes (its cgroup's limit,
:func:`raykit_grading.sandbox.confine.container_limits`), L is shared three ways::

    L = G + K + M          at Gradescope's L = 768 MB: 320 + 32 + 416

* G = :data:`GRADER_MEMORY`, the grader's own. Its peak is measured and printed at the end of
  every grading (``the grader's peak memory: N MB of the 320 MB it keeps``); what it does with
  what a test returns is bounded (:func:`raykit_grading.sandbox.returned.read_returned`: 16 arrays,
  16 MB). What the grader does not use of G is the room for what a test can add between two of
  the grader's looks (below).
* K = :func:`kernel_share`, rounded up to a whole 16 MB: what the test's process can make the
  kernel hold that no count of that process shows, each term bounded by a limit:

  ======================================  ==============================================
  pipes' buffers                          64 descriptors x 16 pages (``F_SETPIPE_SZ``,
                                          which would enlarge them, is refused): 4 MB
  the kernel's record of each mapping     ``vm.max_map_count`` (65,530) x 300 bytes: 19 MB
  threads                                 16 x (16 KB kernel stack + 8 KB): 0.4 MB
  queued signals and POSIX timers         ``RLIMIT_SIGPENDING`` (64) x 80 bytes
  open files, and the files and folders   (64 + 4,096) x 1 KB: 4 MB
  of its ``tmp/``
  ======================================  ==============================================

  Refused outright (nothing to count): sockets of every family (their buffers hold up to
  2 x ``net.core.wmem_max`` each, and a unix socket carries open files that no process holds),
  POSIX record locks (``fcntl`` ``F_SETLK``...; each lock costs the kernel a record, as many
  as its CPU time lets it take), epoll, inotify and fanotify instances, AIO contexts, io_uring,
  memfd, System V IPC, POSIX message queues, keyrings, userfaultfd, bpf, perf events.
* M = L - G - K (2 GB at most; 2 GB where no container limit is found), the test's own: its
  process's address-space limit (``RLIMIT_AS``: what it maps can never pass M) and the budget
  of its memory and page tables together (``VmRSS + VmPTE`` of ``/proc/PID/status``), counted
  at every look. Page tables are the one thing the address-space limit does not bound: a
  mapping of two pages across a gigabyte boundary costs four page-table pages, twice what it
  maps, and a process may make ``vm.max_map_count`` of them. Between two looks a test adds
  only what it can map in :data:`WATCH_SECONDS`, which what the grader leaves of G covers.

And a net under all of it: at every look, what the container holds, less the file cache the
kernel can drop at once (``memory.current`` or ``memory.usage_in_bytes``, less
``active_file`` and ``inactive_file``), must stay :data:`CONTAINER_MARGIN` below L, or the
test is stopped. So the container's OOM killer never has to fire; the grader reads how often
it did (``memory.events`` or ``memory.oom_control``), tells a test during which it fired that
it was killed, and prints the count at the end of every grading.

**Disk.** A test may write in its ``tmp/`` only, and hold there at once at most
``DiskBudget`` (64 MB of blocks, 4,096 entries, folders 32 deep): the files it can name
(:func:`raykit_grading.sandbox.leftovers.measure`, a walk of ``tmp/``) and the files with no name
that its process holds (:func:`nameless_bytes`: through a descriptor, a file unlinked while open,
its blocks counted; through a mapping alone, counted as the largest a file may be, since the
grader cannot measure it). ``O_TMPFILE`` is refused (EOPNOTSUPP: Python's ``tempfile`` then
unlinks a named file, which is counted), ``fallocate`` is refused, sparse files cost what
they hold, and no socket can carry a descriptor away from the process. Between two looks the
test can add only what it writes in that time (each file at most ``Limits.file_bytes``). Its
mappings are read again only after :data:`MAPS_SHARE` times what the last reading took (the
kernel writes a line for each of them, up to 65,530), so that the grader's looks take a small
share of the CPU the test and the grader share.

Where no container limit is found (the root and normal-user ways on an instructor's machine),
M is 2 GB and the net is not there: the machine's memory is the instructor's to size.
"""

from __future__ import annotations

import ctypes
import os
import re
import resource
import stat
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from raykit_grading.sandbox.leftovers import DiskBudget, measure

GRADER_MEMORY = 320 * 2**20  # G: what the grader itself may need beside one test
CHILD_MEMORY_FLOOR = 256 * 2**20  # below this a test cannot render; the grader says so
MOST_MEMORY = 2 * 2**30  # M where no container limit is found
CONTAINER_MARGIN = 24 * 2**20  # what the container must keep free at every look
WATCH_SECONDS = 0.05  # how often a running test's memory is counted
DISK_EVERY = 2  # and its disk, every so many looks
MAPS_SHARE = 10  # its mappings, after so many times what the last look at them took
MAPPING_RECORD = 300  # bytes the kernel keeps per mapping (vm_area_struct, its tree, a name)
PIPE_PAGES = 16  # a pipe's buffer, which F_SETPIPE_SZ (refused) would enlarge
THREAD_BYTES = 24 * 2**10  # a thread's kernel stack and record
SIGNAL_BYTES = 80  # a queued signal, or a POSIX timer's
ENTRY_BYTES = 2**10  # an open file's record; a file or folder's inode and name in the cache
SIGNALS_PENDING = 64  # RLIMIT_SIGPENDING of the test's process


def _sysctl(path: str, default: int) -> int:
    try:
        return int(Path(path).read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return default


@dataclass(frozen=True)
class KernelShare:
    """What the kernel may hold for a test beyond what its process's counts show, in bytes,
    term by term (see the module's docstring)."""

    pipes: int
    mappings: int
    threads: int
    signals: int
    entries: int

    @property
    def total(self) -> int:
        """The sum, rounded up to a whole 16 MB."""
        exact = self.pipes + self.mappings + self.threads + self.signals + self.entries
        return -(-exact // (16 * 2**20)) * 16 * 2**20


def kernel_share(open_files: int, threads: int, disk: DiskBudget) -> KernelShare:
    """K for a test of ``open_files`` descriptors, ``threads`` threads and ``disk``, on this
    machine (its page size and ``vm.max_map_count``)."""
    page = os.sysconf("SC_PAGE_SIZE")
    return KernelShare(
        pipes=open_files * PIPE_PAGES * page,
        mappings=_sysctl("/proc/sys/vm/max_map_count", 65530) * MAPPING_RECORD,
        threads=threads * THREAD_BYTES,
        signals=SIGNALS_PENDING * SIGNAL_BYTES,
        entries=(open_files + disk.entries) * ENTRY_BYTES,
    )


def memory_budget(container_bytes: int | None, kernel: int) -> int:
    """M: what a test's process may hold (address space, and memory with page tables) in a
    container of ``container_bytes`` (None: no limit found), beside the grader's G and the
    kernel's K; never less than :data:`CHILD_MEMORY_FLOOR`."""
    if container_bytes is None:
        return MOST_MEMORY
    return min(MOST_MEMORY, max(CHILD_MEMORY_FLOOR, container_bytes - GRADER_MEMORY - kernel))


def grader_peak() -> int:
    """The grader process's own peak memory so far (its largest resident set), in bytes: its
    VmHWM. Not getrusage's ru_maxrss, which Linux carries across exec: a grader started from a
    large process (a test runner's worker, a batch) would report that process's resident set."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


# ---- the container's memory --------------------------------------------------------------------


class ContainerMemory:
    """What the container (the cgroup whose limit is the tightest) holds, and how often its
    OOM killer fired; cgroup v2 or v1. Reads never raise: what cannot be read is None."""

    def __init__(self, folder: Path, limit: int, v2: bool) -> None:
        self.folder, self.limit, self.v2 = Path(folder), limit, v2

    def _read(self, name: str) -> str | None:
        try:
            return (self.folder / name).read_text()
        except OSError:
            return None

    def held(self) -> int | None:
        """What it holds less the file cache the kernel can drop: anonymous memory, page
        tables and the kernel's own records, all that an OOM killer would be called for."""
        usage = self._read("memory.current" if self.v2 else "memory.usage_in_bytes")
        stats = self._read("memory.stat")
        if usage is None or stats is None:
            return None
        prefix = "" if self.v2 else "total_"
        values = dict(line.split()[:2] for line in stats.splitlines() if line.count(" ") >= 1)
        cache = sum(int(values.get(f"{prefix}{k}", 0)) for k in ("active_file", "inactive_file"))
        return int(usage.split()[0]) - cache

    def oom_kills(self) -> int | None:
        """How often its OOM killer has fired (None: the kernel does not say)."""
        text = self._read("memory.events" if self.v2 else "memory.oom_control")
        found = re.search(r"^oom_kill (\d+)", text or "", re.M)
        return int(found.group(1)) if found else None


# ---- the test's process ----------------------------------------------------------------------

_libc = ctypes.CDLL(None, use_errno=True)


@contextmanager
def looking_as(ids: tuple[int, int] | None):
    """Read /proc as ``(uid, gid)`` (this thread's file-system ids, as root): /proc lets a
    process of the same ids look at another's descriptors and mappings, where root in Docker
    has no CAP_SYS_PTRACE to look at anyone's. None: as it is. (Root with other file-system
    ids also loses CAP_DAC_OVERRIDE meanwhile.)"""
    if ids is None:
        yield
        return
    uid, gid = ids
    _libc.setfsgid(gid)
    _libc.setfsuid(uid)
    try:
        yield
    finally:
        _libc.setfsuid(0)
        _libc.setfsgid(0)


def descendant(pid: int, depth: int) -> int | None:
    """The process ``depth`` generations below ``pid`` (its first child each time), or None
    while there is none yet."""
    for _ in range(depth):
        try:
            children = Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
        except OSError:
            return None
        if not children:
            return None
        pid = int(children[0])
    return pid


def live_task(pid: int) -> tuple[str, str] | None:
    """(``/proc/PID/task/TID``, its status) of a thread of process ``pid`` that still has the
    process's memory and descriptors (the leader's, unless it alone has exited), or None once
    the process has ended or is ending."""
    for tid in _threads(pid):
        base = f"/proc/{pid}/task/{tid}"
        try:
            status = Path(f"{base}/status").read_text()
        except OSError:
            continue
        if "VmRSS:" in status and not re.search(r"^State:\s+[ZX]", status, re.M):
            return base, status
    return None


def _threads(pid: int):
    """The process's leader first, then (only if need be) its other threads."""
    yield str(pid)
    try:
        yield from (tid for tid in os.listdir(f"/proc/{pid}/task") if tid != str(pid))
    except OSError:
        return


def process_memory(pid: int) -> int | None:
    """``VmRSS + VmPTE`` of process ``pid`` in bytes (its memory and page tables), None once
    it is gone."""
    task = live_task(pid)
    found = dict(re.findall(r"^(VmRSS|VmPTE):\s+(\d+) kB", task[1] if task else "", re.M))
    return (int(found["VmRSS"]) + int(found["VmPTE"])) * 1024 if len(found) == 2 else None


class Hidden(Exception):
    """The grader may not look at a test's descriptors (it made itself undumpable)."""


class Gone(Exception):
    """The test's process ended while the grader looked."""


def nameless_bytes(pid: int, device: int, file_bytes: int, ids=None, mapped=None) -> int:
    """Disk blocks that process ``pid`` holds in files with no name on ``device`` (its
    ``tmp/``'s): through a descriptor, the file's own blocks; through a mapping alone, the
    largest a file may be (``file_bytes``: the grader cannot measure it). ``mapped``: the
    inodes :func:`mapped_nameless` found at an earlier look, instead of looking again. Raises
    :class:`Hidden` if the process keeps the grader from looking, :class:`Gone` if it has
    ended (an ending process's descriptors are closed to all but root)."""
    held = descriptor_nameless(pid, device, ids)
    mapped = mapped_nameless(pid, device, ids) if mapped is None else mapped
    return sum(held.values()) + file_bytes * len(mapped - held.keys())


def _task_or_gone(pid: int) -> str:
    task = live_task(pid)
    if task is None:
        raise Gone
    return task[0]


def _refused(pid: int) -> Exception:
    return Hidden() if live_task(pid) else Gone()


def descriptor_nameless(pid: int, device: int, ids=None) -> dict[int, int]:
    """{inode: its blocks in bytes} of the files with no name on ``device`` that process
    ``pid`` holds open (:func:`nameless_bytes`)."""
    base, held = _task_or_gone(pid), {}
    with looking_as(ids):
        try:
            names = os.listdir(f"{base}/fd")
        except (FileNotFoundError, ProcessLookupError):
            raise Gone from None
        except PermissionError:
            raise _refused(pid) from None
        for name in names:
            try:
                info = os.stat(f"{base}/fd/{name}")
            except (FileNotFoundError, ProcessLookupError):
                continue
            except PermissionError:
                raise _refused(pid) from None
            if stat.S_ISREG(info.st_mode) and info.st_nlink == 0 and info.st_dev == device:
                held[info.st_ino] = info.st_blocks * 512
    return held


DELETED = b" (deleted)\n"  # how /proc/PID/maps ends the line of a file with no name


def mapped_nameless(pid: int, device: int, ids=None) -> set[int]:
    """The inodes of the files with no name on ``device`` that process ``pid`` maps (read from
    ``/proc/PID/maps`` at once and only the lines of deleted files parsed: a test may have
    65,530 mappings, and the grader's look must not cost it its time)."""
    base = _task_or_gone(pid)
    with looking_as(ids):
        try:
            with open(f"{base}/maps", "rb") as maps:
                text = maps.read()
        except (FileNotFoundError, ProcessLookupError):
            raise Gone from None
        except PermissionError:
            raise _refused(pid) from None
    found, end = set(), text.find(DELETED)
    while end != -1:  # each such line: address, permissions, offset, major:minor, inode, path
        fields = text[text.rfind(b"\n", 0, end) + 1 : end].split(maxsplit=5)
        major, minor = (int(part, 16) for part in fields[3].split(b":"))
        if os.makedev(major, minor) == device:
            found.add(int(fields[4]))
        end = text.find(DELETED, end + 1)
    return found


class Watch:
    """What one running test holds, counted at each look (``watch()`` returns "" while every
    count is within its budget, else what it passed, as the test's problem).

    ``root``: the process the sandbox started; ``depth``: how many generations below it the
    test's own process is (bubblewrap: its pid namespace's init, then the test; chroot: the
    test itself); ``tmp``: the test's ``tmp/``; ``ids``: the ids to look at its process as
    (:func:`looking_as`) where the grader's own may not (root without CAP_SYS_PTRACE, in
    Docker); the grader's own are tried first (a process that changed its uid without an
    ``exec``, as bubblewrap's does, is open to root alone)."""

    def __init__(self, limits, container: ContainerMemory | None, root: int, depth: int,
                 tmp: Path, ids: tuple[int, int] | None) -> None:  # fmt: skip
        self.limits, self.container = limits, container
        self.root, self.depth, self.tmp, self.ids = root, depth, Path(tmp), ids
        self.pid: int | None = None
        self.looked_as: tuple[int, int] | None | str = ""  # as which ids /proc let it look
        self.looks = 0
        self.mapped: set[int] = set()  # the mapped files with no name, at the last look at them
        self.maps_due = 0.0  # when the mappings are looked at again (time.monotonic())
        try:
            self.device = os.stat(tmp).st_dev
        except OSError:
            self.device = -1

    def __call__(self) -> str:
        """One look: memory every time, disk every :data:`DISK_EVERY` looks (a walk of its
        ``tmp/`` and of its open files and mappings costs more, and disk fills slower)."""
        limits = self.limits
        self.looks += 1
        if self.pid is None:
            self.pid = descendant(self.root, self.depth)
        if self.pid is not None:
            memory = process_memory(self.pid)
            if memory is not None and memory > limits.memory_bytes:
                return (
                    f"your code used more memory than allowed: its memory and page tables "
                    f"came to more than {limits.memory_bytes // 2**20} MB, and it was stopped"
                )
        if self.container is not None:
            held = self.container.held()
            if held is not None and held > self.container.limit - CONTAINER_MARGIN:
                return (
                    f"your code used more memory than allowed: the container's memory ran short "
                    f"({held // 2**20} MB of {self.container.limit // 2**20} MB held), and it "
                    "was stopped"
                )
        return self.disk() if (self.looks - 1) % DISK_EVERY == 0 else ""

    def disk(self) -> str:
        """The disk budget: the files its ``tmp/`` names and those with no name it holds (its
        mappings looked at again only after :data:`MAPS_SHARE` times what the last look at
        them took, so that the grader's looks take a small share of the time they watch)."""
        limits, nameless = self.limits, 0
        if self.pid is not None:
            for ids in [self.looked_as] if self.looked_as != "" else [None, self.ids]:
                try:
                    held = descriptor_nameless(self.pid, self.device, ids)
                    if time.monotonic() >= self.maps_due:
                        began = time.monotonic()
                        self.mapped = mapped_nameless(self.pid, self.device, ids)
                        self.maps_due = time.monotonic() + MAPS_SHARE * (time.monotonic() - began)
                    mapped_alone = len(self.mapped - held.keys())
                    nameless = sum(held.values()) + limits.file_bytes * mapped_alone
                    self.looked_as = ids
                    break
                except Gone:
                    break
                except Hidden:
                    continue
            else:
                return "your code kept the grader from looking at its open files, and was stopped"
        passed = measure(self.tmp, limits.disk, nameless)
        return disk_problem(passed, limits.disk, nameless)


def disk_problem(passed: str, disk: DiskBudget, nameless: int = 0) -> str:
    """The problem of a test whose disk passed its budget ("" if it did not)."""
    if not passed:
        return ""
    unnamed = f" ({nameless // 2**20} MB of it in files with no name)" if nameless else ""
    return (
        f"your code used more disk than allowed: it wrote {passed} in its tmp/ folder{unnamed} "
        f"and was stopped (a test may keep at most {disk.describe()} there)"
    )

"""Run a command as root the way Docker's default confinement would (Gradescope's container).

    python tests/support/docker_confinement.py [--memory-mb 768] [--cpus 0.5] [--report] \
        -- COMMAND...

The command runs with:

* the capability bounding set cut to Docker's default 14 (CHOWN, DAC_OVERRIDE, FOWNER, FSETID,
  KILL, SETGID, SETUID, SETPCAP, NET_BIND_SERVICE, NET_RAW, SYS_CHROOT, MKNOD, AUDIT_WRITE,
  SETFCAP), and every other capability dropped from its effective, permitted and inheritable
  sets;
* a seccomp filter with the rules of moby's ``profiles/seccomp/default.json`` that matter to
  a sandbox, for a container without CAP_SYS_ADMIN: ``unshare``, ``setns``, ``mount``,
  ``umount2`` and a ``clone`` with any ``CLONE_NEW*`` flag fail with EPERM, ``clone3`` with
  ENOSYS (so that the C library falls back to ``clone``, whose flags can be seen);
* optionally, a cgroup v1 memory limit (``--memory-mb``) and CPU quota (``--cpus``) of its own.

Exit status: the command's; 77 (and one line saying why) if this machine cannot make the
emulation (not root, no writable cgroup when one is asked for).
"""

from __future__ import annotations

import argparse
import ctypes
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO))

from raykit_grading.sandbox.confine import _cgroup_folders, install_seccomp  # noqa: E402
from raykit_grading.sandbox.isolation import SECCOMP_ARCHES, bpf_program  # noqa: E402

CANNOT = 77
DOCKER_CAPABILITIES = {
    "CHOWN": 0, "DAC_OVERRIDE": 1, "FOWNER": 3, "FSETID": 4, "KILL": 5, "SETGID": 6,
    "SETUID": 7, "SETPCAP": 8, "NET_BIND_SERVICE": 10, "NET_RAW": 13, "SYS_CHROOT": 18,
    "MKNOD": 27, "AUDIT_WRITE": 29, "SETFCAP": 31,
}  # fmt: skip
CALLS = {  # (unshare, setns, mount, umount2, clone, clone3)
    "x86_64": (272, 308, 165, 166, 56, 435),
    "aarch64": (97, 268, 40, 39, 220, 435),
}
CLONE_NEW_FLAGS = 0x7E020000  # the mask default.json tests clone's flags against
PR_CAPBSET_DROP = 24
ERRNO, EPERM, ENOSYS, ALLOW = 0x00050000, 1, 38, 0x7FFF0000


def docker_seccomp(machine: str | None = None) -> bytes:
    machine = machine or platform.machine()
    arch = SECCOMP_ARCHES[machine][0]
    unshare, setns, mount, umount2, clone, clone3 = CALLS[machine]
    steps: list[tuple] = [("ld", 4), ("jeq", arch, None, "allow"), ("ld", 0)]
    steps += [("jeq", n, "eperm", None) for n in (unshare, setns, mount, umount2)]
    steps += [("jeq", clone3, "enosys", None), ("jeq", clone, "clone", "allow")]
    steps += [("label", "clone"), ("ld", 16), ("jset", CLONE_NEW_FLAGS, "eperm", "allow")]
    steps += [("label", "allow"), ("ret", ALLOW), ("label", "eperm"), ("ret", ERRNO | EPERM)]
    steps += [("label", "enosys"), ("ret", ERRNO | ENOSYS)]
    return bpf_program(steps)


class _CapHeader(ctypes.Structure):
    _fields_ = [("version", ctypes.c_uint32), ("pid", ctypes.c_int)]


class _CapData(ctypes.Structure):
    _fields_ = [("effective", ctypes.c_uint32), ("permitted", ctypes.c_uint32),
                ("inheritable", ctypes.c_uint32)]  # fmt: skip


def drop_to_docker_capabilities() -> None:
    libc = ctypes.CDLL(None, use_errno=True)
    keep = set(DOCKER_CAPABILITIES.values())
    last = int(Path("/proc/sys/kernel/cap_last_cap").read_text())
    for cap in range(last + 1):
        if cap not in keep and libc.prctl(PR_CAPBSET_DROP, cap, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), f"PR_CAPBSET_DROP {cap}")
    mask = sum(1 << cap for cap in keep)
    header = _CapHeader(0x20080522, 0)  # _LINUX_CAPABILITY_VERSION_3
    data = (_CapData * 2)(_CapData(mask, mask, 0), _CapData(0, 0, 0))
    if libc.capset(ctypes.byref(header), data) != 0:
        raise OSError(ctypes.get_errno(), "capset")


def make_cgroup(controller: str, name: str, settings: dict[str, str]) -> Path:
    """A child of this process's v1 cgroup for ``controller`` with ``settings`` written."""
    folders = _cgroup_folders(controller)
    if not folders:
        raise OSError(f"no cgroup v1 {controller} hierarchy here")
    folder = folders[0] / name
    folder.mkdir()
    for key, value in settings.items():
        (folder / key).write_text(value)
    return folder


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, allow_abbrev=False)
    parser.add_argument("--memory-mb", type=int)
    parser.add_argument("--cpus", type=float)
    parser.add_argument(
        "--report",
        action="store_true",
        help="say the wall time, the peak memory used and how often the OOM killer fired",
    )
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if os.geteuid() != 0:
        print("docker_confinement: needs root (Docker's root, cut down)", file=sys.stderr)
        return CANNOT
    if platform.machine() not in CALLS:
        print(f"docker_confinement: no filter for {platform.machine()}", file=sys.stderr)
        return CANNOT
    made: list[Path] = []
    try:
        name = f"raykit-docker-{os.getpid()}"
        if args.memory_mb:
            limit = str(args.memory_mb * 2**20)
            made.append(make_cgroup("memory", name, {"memory.limit_in_bytes": limit}))
        if args.cpus:
            quota = {"cpu.cfs_period_us": "100000", "cpu.cfs_quota_us": str(int(args.cpus * 1e5))}
            made.append(make_cgroup("cpu", name, quota))
    except OSError as exc:
        print(f"docker_confinement: cannot make a cgroup: {exc}", file=sys.stderr)
        for folder in made:
            folder.rmdir()
        return CANNOT
    program = docker_seccomp()

    def confine() -> None:
        for folder in made:
            (folder / "cgroup.procs").write_text(str(os.getpid()))
        install_seccomp(program)  # as full root: needs no NO_NEW_PRIVS, as Docker's runtime
        drop_to_docker_capabilities()

    start = time.perf_counter()
    try:
        return subprocess.run(command, preexec_fn=confine).returncode  # noqa: PLW1509
    finally:
        if args.report:
            said = [f"wall {time.perf_counter() - start:.1f} s"]
            for folder in made:
                if (folder / "memory.max_usage_in_bytes").exists():
                    peak = int((folder / "memory.max_usage_in_bytes").read_text())
                    said.append(f"peak memory {peak / 2**20:.0f} MB")
                    control = (folder / "memory.oom_control").read_text().split()
                    if "oom_kill" in control:
                        said.append(f"OOM kills {control[control.index('oom_kill') + 1]}")
            print(f"docker_confinement: {', '.join(said)}", file=sys.stderr)
        for folder in made:
            for _ in range(100):  # the command's last processes may still be exiting
                try:
                    folder.rmdir()
                    break
                except OSError:
                    time.sleep(0.05)


if __name__ == "__main__":
    sys.exit(main())

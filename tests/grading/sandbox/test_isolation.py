"""The grader's machinery around the sandbox: uid leases, workspaces, staging, what ships."""

from __future__ import annotations

import fcntl
import json
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import zipfile
from pathlib import Path

import pytest
import tomllib

from conftest import REPO
from raykit_grading.grading.submissions import MAX_BYTES, SubmissionError, stage
from raykit_grading.sandbox import isolation
from raykit_grading.sandbox.confine import ContainerLimits, container_limits, landlock_abi
from raykit_grading.sandbox.isolation import SANDBOX_UIDS, UidPool, kill_uid
from raykit_grading.sandbox.workspace import PREFIX, Workspace, clean_stale

AS_ROOT = os.geteuid() == 0


@pytest.mark.skipif(not AS_ROOT, reason="sandbox uids are leased only when grading as root")
def test_two_graders_never_lease_the_same_uid(tmp_path):
    locks = tmp_path / "uids"
    first, second = UidPool(range(61000, 61003), locks), UidPool(range(61000, 61003), locks)
    leases = [first.lease(), second.lease(), first.lease()]
    assert len({lease.uid for lease in leases}) == 3
    with pytest.raises(RuntimeError, match="all 3 sandbox uids are in use"):
        second.lease()
    leases[1].release()
    assert second.lease().uid == leases[1].uid


def _unreaped_process_of(uid: int, reap_after: float) -> subprocess.Popen:
    """A process of ``uid`` that, once killed, stays in /proc as a zombie until this test
    reaps it, ``reap_after`` seconds from now (as a process slow to die would)."""
    child = subprocess.Popen(["sleep", "60"], user=uid, group=uid)
    threading.Timer(reap_after, child.wait).start()
    return child


@pytest.mark.skipif(not AS_ROOT, reason="sandbox uids are leased only when grading as root")
def test_a_uid_is_given_back_only_once_its_processes_have_left_proc():
    child = _unreaped_process_of(61010, reap_after=0.5)
    kill_uid(61010)
    assert child.returncode == -9 and not Path(f"/proc/{child.pid}").exists()


@pytest.mark.skipif(not AS_ROOT, reason="sandbox uids are leased only when grading as root")
def test_processes_that_outlast_the_kill_wait_are_reported(monkeypatch, capfd):
    monkeypatch.setattr(isolation, "KILL_WAIT_SECONDS", 0.2)
    child = _unreaped_process_of(61011, reap_after=1.0)
    kill_uid(61011)
    assert f"sandbox uid 61011 still has processes ['{child.pid}']" in capfd.readouterr().err
    child.wait()


def test_a_killed_graders_workspace_is_removed_by_the_next_one(tmp_path):
    stale = tmp_path / f"{PREFIX}stale"
    stale.mkdir()
    (stale / ".lock").write_text("")
    (stale / "task-1").mkdir()
    busy = tmp_path / f"{PREFIX}busy"
    busy.mkdir()
    held = os.open(busy / ".lock", os.O_RDWR | os.O_CREAT)
    fcntl.flock(held, fcntl.LOCK_EX)  # a grader still running
    unlocked_old = tmp_path / f"{PREFIX}never-locked"
    unlocked_old.mkdir()
    os.utime(unlocked_old, (time.time() - 3600, time.time() - 3600))
    try:
        with Workspace(tmp_path) as mine:
            assert mine.is_dir() and (mine / ".lock").is_file()
            assert clean_stale(tmp_path) == []  # its own is locked
        assert not stale.exists() and not unlocked_old.exists() and busy.exists()
        assert not mine.exists()
    finally:
        os.close(held)


def test_staging_copies_plain_files_and_names_what_it_leaves_out(tmp_path):
    source = tmp_path / "submission"
    (source / "raykit" / "sub").mkdir(parents=True)
    (source / "raykit" / "__init__.py").write_text("")
    (source / "raykit" / "sub" / "x.py").write_text("X = 1\n")
    (source / "raykit" / "link.py").symlink_to("/etc/passwd")
    os.mkfifo(source / "raykit" / "pipe.py")
    staged = stage(source, tmp_path / "staged")
    assert staged.package == tmp_path / "staged" / "raykit"
    assert (staged.package / "sub" / "x.py").read_text() == "X = 1\n"
    assert not (staged.package / "link.py").exists()
    assert not (staged.package / "pipe.py").exists()
    assert staged.notes == [
        "raykit/link.py is a symbolic link: left out (only plain files count)",
        "raykit/pipe.py is a named pipe (FIFO): left out (only plain files count)",
    ]


def test_staging_refuses_a_zip_that_escapes_or_inflates(tmp_path):
    for name, members in {
        "escape": {"raykit/../../evil.py": b"x"},
        "bomb": {
            "raykit/__init__.py": b"",
            **{f"raykit/big{i}.py": b"\0" * (MAX_BYTES // 2) for i in range(3)},
        },
    }.items():
        source = tmp_path / name
        source.mkdir()
        with zipfile.ZipFile(source / "work.zip", "w", zipfile.ZIP_DEFLATED) as archive:
            for member, data in members.items():
                archive.writestr(member, data)
        with pytest.raises(SubmissionError):
            stage(source, tmp_path / f"{name}-staged")
    assert not (tmp_path / "evil.py").exists()


def test_the_wheel_holds_raykit_and_its_grader_but_no_hidden_scenes():
    from setuptools import find_packages

    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages = find_packages(str(REPO), include=config["packages"]["find"]["include"])
    assert "grading" not in packages and "raykit_grading" in packages
    assert {p.split(".")[0] for p in packages} == {"raykit", "raykit_grading"}
    data = config.get("package-data", {})
    assert all("scenes" not in pattern for patterns in data.values() for pattern in patterns)
    assert not list((REPO / "raykit_grading").rglob("*.json"))


def test_the_grader_says_plainly_when_it_has_no_clone_to_read_scenes_from(monkeypatch, tmp_path):
    import raykit_grading.grading.grade as grade

    monkeypatch.setattr(grade, "HIDDEN_SCENES", tmp_path / "nowhere")
    with pytest.raises(grade.GradingImpossible, match="needs a clone of the course repository"):
        grade.check_clone()


def test_the_zip_holds_at_its_top_what_gradescope_puts_in_autograder_source(tmp_path):
    """Gradescope extracts the zip into /autograder/source: setup.sh, run_autograder, the
    requirements, the seed and the grader's packages are at the zip's top, not in a folder."""
    from raykit_grading.platforms.gradescope import REQUIREMENTS, build_zip

    with zipfile.ZipFile(build_zip(tmp_path / "ag.zip")) as archive:
        setup = archive.read("setup.sh").decode()
        names = archive.namelist()
        pinned = archive.read("grader-requirements.txt")
    tops = {name.split("/", 1)[0] for name in names}
    assert tops == {"setup.sh", "run_autograder", "grader-requirements.txt", "grading-seed",
                    "raykit", "raykit_grading", "scenes", "grading"}  # fmt: skip
    assert "raykit_grading/__main__.py" in names and "grading/hidden-scenes/odd.json" in names
    assert pinned == REQUIREMENTS.read_bytes()
    assert '-r "$source/grader-requirements.txt"' in setup and "bubblewrap" in setup
    assert not any("__pycache__" in name for name in names)


# ---- the sandboxes' kernel pieces, and where each is used -----------------------------------

EMULATION = REPO / "tests" / "support" / "docker_confinement.py"
NOBODY = 65534

SECCOMP_PROBE = """
import ctypes, errno, fcntl, json, os, select, socket, sys, tempfile, threading
sys.path.insert(0, {repo!r})
from raykit_grading.sandbox.confine import install_seccomp, no_new_privileges
from raykit_grading.sandbox.isolation import CLONE_CALLS, SECCOMP_ARCHES, seccomp_filter
import platform
calls = SECCOMP_ARCHES[platform.machine()][1]
no_new_privileges()
install_seccomp(seccomp_filter())
libc = ctypes.CDLL(None, use_errno=True)
said = {{}}


def said_of(name, action):
    try:
        action()
        said[name] = "made"
    except OSError as exc:
        said[name] = errno.errorcode[exc.errno]


for name, family in (("inet", socket.AF_INET), ("inet6", socket.AF_INET6),
                     ("netlink", socket.AF_NETLINK), ("unix", socket.AF_UNIX)):
    said_of(name, lambda: socket.socket(family, socket.SOCK_DGRAM).close())
said_of("socketpair", socket.socketpair)
for name in ("keyctl", "ptrace", "unshare", "bpf", "shmget", "mq_open", "fsopen", "memfd_create",
             "inotify_init1", "fanotify_init", "io_setup"):
    libc.syscall(calls[name], 0, 0, 0, 0)
    said[name] = errno.errorcode.get(ctypes.get_errno(), "none")
said_of("epoll", lambda: select.epoll().close())
clone, clone3 = CLONE_CALLS[platform.machine()]
for name, flags in (("clone_newuser", 0x10000000), ("clone_newns", 0x00020000), ("fork", 0),
                    ("vfork", 0x4000 | 0x100)):
    ctypes.set_errno(0)
    pid = libc.syscall(clone, flags | 17, 0, 0, 0, 0)  # SIGCHLD
    if pid == 0:
        os._exit(0)
    said[name] = "made" if pid > 0 else errno.errorcode.get(ctypes.get_errno(), "none")
    if pid > 0:
        os.waitpid(pid, 0)
libc.syscall(clone3, None, 0)
said["clone3"] = errno.errorcode.get(ctypes.get_errno(), "none")
ran = []
thread = threading.Thread(target=lambda: ran.append(1))
thread.start()
thread.join()
said["thread"] = "made" if ran else "none"
said_of("O_TMPFILE", lambda: os.close(os.open("/tmp", os.O_TMPFILE | os.O_RDWR, 0o600)))
said_of("TemporaryFile", lambda: tempfile.TemporaryFile(dir="/tmp").close())
read, write = os.pipe()
said_of("pipe bigger", lambda: fcntl.fcntl(write, 1031, 2**20))  # F_SETPIPE_SZ
said_of("record lock", lambda: fcntl.lockf(tempfile.TemporaryFile(dir="/tmp"), fcntl.LOCK_EX))
said_of("flock", lambda: fcntl.flock(tempfile.TemporaryFile(dir="/tmp"), fcntl.LOCK_EX))
print(json.dumps(said))
"""


def test_the_seccomp_filter_refuses_the_network_kernel_state_and_a_second_process():
    """What would reach kernel state no namespace isolates, hold kernel memory no limit of
    the test's process counts, or make a second process is refused; threads, Python's
    temporary files, pipes and flock still work."""
    run = subprocess.run(
        [sys.executable, "-c", SECCOMP_PROBE.format(repo=str(REPO))],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout) == {
        "inet": "EPERM", "inet6": "EPERM", "netlink": "EPERM", "unix": "EPERM",
        "socketpair": "EPERM", "keyctl": "EPERM", "ptrace": "EPERM", "unshare": "EPERM",
        "bpf": "EPERM", "shmget": "EPERM", "mq_open": "EPERM", "fsopen": "EPERM",
        "memfd_create": "EPERM", "inotify_init1": "EPERM", "fanotify_init": "EPERM",
        "io_setup": "EPERM", "epoll": "EPERM", "clone_newuser": "EPERM", "clone_newns": "EPERM",
        "fork": "EPERM", "vfork": "EPERM", "clone3": "ENOSYS", "thread": "made",
        "O_TMPFILE": "ENOTSUP", "TemporaryFile": "made", "pipe bigger": "EPERM",
        "record lock": "EPERM", "flock": "made",
    }  # fmt: skip


def _fake_proc(tmp_path, cgroup: str, mounts: list[tuple[str, str, str, str]]):
    """A /proc/self with these cgroup lines and (root, mountpoint, fstype, options) mounts."""
    proc = tmp_path / "proc"
    proc.mkdir()
    (proc / "cgroup").write_text(cgroup)
    lines = [f"{30 + i} 1 0:{i} {root} {point} rw - {kind} cgroup {options}"
             for i, (root, point, kind, options) in enumerate(mounts)]  # fmt: skip
    (proc / "mountinfo").write_text("\n".join(lines) + "\n")
    return proc


def test_the_container_limits_are_read_from_cgroup_v2_and_v1(tmp_path):
    v2 = tmp_path / "v2"
    (v2 / "docker/abc").mkdir(parents=True)
    (v2 / "memory.max").write_text("max\n")
    (v2 / "cpu.max").write_text("max 100000\n")
    (v2 / "docker/memory.max").write_text(f"{1024 * 2**20}\n")
    (v2 / "docker/abc/memory.max").write_text(f"{768 * 2**20}\n")
    (v2 / "docker/abc/cpu.max").write_text("50000 100000\n")
    proc = _fake_proc(tmp_path, "0::/docker/abc\n", [("/", str(v2), "cgroup2", "rw")])
    assert container_limits(proc) == ContainerLimits(768 * 2**20, 0.5)

    memory, cpu = tmp_path / "memory", tmp_path / "cpu"
    (memory / "grader").mkdir(parents=True)
    (cpu / "grader").mkdir(parents=True)
    (memory / "memory.limit_in_bytes").write_text("9223372036854771712\n")
    (memory / "grader/memory.limit_in_bytes").write_text(f"{512 * 2**20}\n")
    (cpu / "grader/cpu.cfs_quota_us").write_text("150000\n")
    (cpu / "grader/cpu.cfs_period_us").write_text("100000\n")
    (tmp_path / "v1").mkdir()
    proc = _fake_proc(
        tmp_path / "v1",
        "5:memory:/grader\n4:cpu,cpuacct:/grader\n0::/\n",
        [("/", str(memory), "cgroup", "rw,memory"), ("/", str(cpu), "cgroup", "rw,cpu,cpuacct")],
    )
    assert container_limits(proc) == ContainerLimits(512 * 2**20, 1.5)


def test_a_childs_memory_is_cut_to_what_the_container_leaves_beside_the_grader_and_kernel():
    """L = G + K + M (raykit_grading.sandbox.budgets): at Gradescope's 768 MB the test may hold
    416 MB, the kernel 32 MB for it, the grader 320 MB; with no limit found, 2 GB."""
    from raykit_grading.sandbox.base import Limits, fit_to_container
    from raykit_grading.sandbox.budgets import GRADER_MEMORY, kernel_share

    limits = Limits(memory_bytes=2 * 1024**3)
    kernel = kernel_share(limits.open_files, limits.processes, limits.disk)
    assert kernel.total == 32 * 2**20 and kernel.pipes == 4 * 2**20  # 64 pipes of 16 pages
    gradescope = fit_to_container(limits, ContainerLimits(768 * 2**20, 0.5))
    assert gradescope.memory_bytes + GRADER_MEMORY + kernel.total == 768 * 2**20
    assert gradescope.memory_bytes == 416 * 2**20
    assert fit_to_container(limits, ContainerLimits(None, None)) == limits
    assert fit_to_container(limits, ContainerLimits(64 * 2**30, 4)) == limits


def _emulated(command: list[str], memory_mb: int | None = 768, **kw) -> subprocess.CompletedProcess:
    """``command`` as root under Docker's default confinement (tests/support/docker_confinement.py);
    skips, saying why, where this machine cannot make it."""
    if not AS_ROOT:
        pytest.skip("emulating Docker's confinement needs root")
    memory = ["--memory-mb", str(memory_mb)] if memory_mb else []
    run = subprocess.run([sys.executable, str(EMULATION), *memory, "--", *command],
                         capture_output=True, text=True, timeout=600, **kw)  # fmt: skip
    if run.returncode == 77:
        pytest.skip(run.stderr.strip())
    return run


def test_the_docker_emulation_keeps_dockers_14_capabilities_and_refuses_namespaces():
    run = _emulated(
        [
            "bash",
            "-c",
            "grep CapEff /proc/self/status; grep memory /proc/self/cgroup;"
            "unshare --user true || echo REFUSED; bwrap --ro-bind / / true || echo NO-BWRAP",
        ]
    )
    from docker_confinement import DOCKER_CAPABILITIES

    mask = sum(1 << cap for cap in DOCKER_CAPABILITIES.values())
    assert f"CapEff:\t{mask:016x}" in run.stdout
    assert "raykit-docker-" in run.stdout  # in a memory cgroup of its own
    assert "REFUSED" in run.stdout and "NO-BWRAP" in run.stdout
    assert "Operation not permitted" in run.stderr


FACTS = """
import ctypes, errno, json, os, socket
import numpy as np
def plane_side(p, a, n):
    libc = ctypes.CDLL(None, use_errno=True)
    facts = {"uid": os.getuid(), "gid": os.getgid(), "groups": os.getgroups()}
    facts["no_new_privs"] = libc.prctl(39, 0, 0, 0, 0)
    facts["seccomp"] = libc.prctl(21, 0, 0, 0, 0)
    header, data = (ctypes.c_uint32 * 2)(0x20080522, 0), (ctypes.c_uint32 * 6)()
    libc.capget(header, data)
    facts["capabilities"] = list(data)
    def tried(action):
        try:
            action()
            return "yes"
        except OSError as exc:
            return errno.errorcode[exc.errno]
    facts["list /"] = tried(lambda: os.listdir("/"))
    facts["list /tasks"] = tried(lambda: os.listdir("/tasks"))
    facts["read /proc"] = tried(lambda: open("/proc/1/cmdline").read())
    facts["write here"] = tried(lambda: open("x", "w").close())
    facts["write tmp"] = tried(lambda: open(os.environ["TMPDIR"] + "/x", "w").close())
    facts["inet"] = tried(lambda: socket.socket())
    facts["signal 1"] = tried(lambda: os.kill(1, 0))
    facts["signal parent"] = tried(lambda: os.kill(os.getppid(), 0))
    print("FACTS", json.dumps(facts))
    return np.zeros(len(p))
"""

CHROOT_RUN = """
import json, os, sys, tempfile
from pathlib import Path
sys.path.insert(0, {repo!r})
import numpy as np
from raykit_grading.sandbox.kinds import choose_sandbox
from raykit_grading.sandbox.workspace import Workspace
with Workspace() as workspace:
    sandbox = choose_sandbox(Path({submission!r}), workspace, kind={kind!r})
    ran = sandbox.run("plane_side", {{}}, {{k: np.zeros((2, 3)) for k in ("p", "a", "n")}})
    print(sandbox.description, ran.problem)
    print(ran.output)
"""


@pytest.mark.parametrize("where", ["root", "docker"])
def test_the_chroot_childs_uid_capabilities_files_network_and_signals(where, tmp_path):
    """Its own uid (no groups, no capability, no new privileges), the seccomp filter, a tree
    with nothing of the grader's (no /proc, no other test's folder), writing only its tmp, no
    network, no signal to anything outside."""
    if not AS_ROOT:
        pytest.skip("the chroot sandbox is made by root")
    submission = tmp_path / "submission"
    (submission / "raykit").mkdir(parents=True)
    (submission / "raykit/__init__.py").write_text("")
    (submission / "raykit/planes.py").write_text(FACTS)
    os.chmod(tmp_path, 0o755)
    script = CHROOT_RUN.format(repo=str(REPO), submission=str(submission), kind="chroot")
    command = [sys.executable, "-c", script]
    run = _emulated(command) if where == "docker" else subprocess.run(
        command, capture_output=True, text=True, timeout=600)  # fmt: skip
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.startswith("chroot+uid+"), run.stdout
    facts = json.loads(run.stdout.split("FACTS ", 1)[1].splitlines()[0])
    assert facts.pop("uid") in SANDBOX_UIDS and facts.pop("gid") in SANDBOX_UIDS
    assert facts == {
        "groups": [], "no_new_privs": 1, "seccomp": 2, "capabilities": [0] * 6,
        "list /": "EACCES" if landlock_abi() else "yes", "list /tasks": "EACCES",
        "read /proc": "ENOENT", "write here": "EACCES", "write tmp": "yes",
        "inet": "EPERM", "signal 1": "EPERM", "signal parent": "EPERM",
    }  # fmt: skip


def test_a_normal_user_without_user_namespaces_is_refused_in_one_line(tmp_path, request):
    """Where bubblewrap cannot make namespaces and the grader is not root, it grades nothing:
    one line that says how to grade safely, exit 3, results.json NOT GRADED."""
    from docker_confinement import docker_seccomp
    from mistaken_submissions import make_submission

    python = sys.executable
    if AS_ROOT:
        if shutil.which("setpriv") is None:
            pytest.skip("as root this needs setpriv to become uid 65534")
        python = request.getfixturevalue("grader_python")  # one uid 65534 can run
    folder = tmp_path / "user"
    if AS_ROOT:  # pytest's own folders are root's alone
        folder = Path(tempfile.mkdtemp(prefix="raykit-user-", dir="/tmp"))
        request.addfinalizer(lambda: shutil.rmtree(folder, ignore_errors=True))
    make_submission(folder / "submission")
    if AS_ROOT:
        subprocess.run(["chown", "-R", f"{NOBODY}:{NOBODY}", str(folder)], check=True)
    program = docker_seccomp()

    def confine() -> None:
        from raykit_grading.sandbox.confine import install_seccomp, no_new_privileges

        if AS_ROOT:
            os.setgroups([])
            os.setgid(NOBODY)
            os.setuid(NOBODY)
        no_new_privileges()
        install_seccomp(program)

    out = folder / "results.json"
    run = subprocess.run(
        [python, "-m", "raykit_grading", "grade", str(folder / "submission"), "-o", str(out),
         "--only", "2.1"],
        capture_output=True, text=True, cwd=folder, timeout=300, preexec_fn=confine,
        env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(REPO), "TMPDIR": str(folder)},
    )  # fmt: skip
    assert run.returncode == 3, run.stderr
    assert run.stderr.startswith(
        "raykit_grading: error: cannot grade: cannot isolate submissions as a normal user here"
    )
    assert len(run.stderr.strip().splitlines()) == 1 and "grade as root" in run.stderr
    assert json.loads(out.read_text())["tests"][0]["output"].startswith("NOT GRADED")


def test_setup_sh_builds_the_chroot_tree_the_sandbox_then_uses(tmp_path):
    """setup.sh's line builds the tree at image build time; a grading then finds it built."""
    from raykit_grading.platforms.gradescope import build_zip
    from raykit_grading.sandbox.isolation import probe_python
    from raykit_grading.sandbox.kinds import choose_sandbox

    with zipfile.ZipFile(build_zip(tmp_path / "ag.zip")) as archive:
        setup = archive.read("setup.sh").decode()
    line = next(line for line in setup.splitlines() if "raykit_grading.sandbox.confine" in line)
    assert line.startswith('PYTHONPATH="$source" /opt/raykit-grader/bin/python -m')
    if not AS_ROOT:
        pytest.skip("the chroot tree is built by root")
    built = subprocess.run(
        [sys.executable, "-m", "raykit_grading.sandbox.confine"], capture_output=True, text=True,
        cwd=REPO, timeout=600,
    )  # fmt: skip
    assert built.returncode == 0, built.stderr
    tree = Path(built.stdout.strip().removeprefix("sandbox tree: "))
    python = probe_python(sys.executable)
    assert (tree / python.executable.lstrip("/")).is_file()
    assert not (tree / python.stdlib.lstrip("/") / "site-packages").exists()
    assert oct(tree.parent.stat().st_mode & 0o777) == "0o700"
    empty = tmp_path / "empty"
    empty.mkdir()
    assert choose_sandbox(empty, tmp_path, kind="chroot").tree == tree


@pytest.mark.skipif(shutil.which("bwrap") is None, reason="the benchmark times bubblewrap too")
def test_the_sandbox_cost_benchmark_times_every_sandbox_kind_this_user_can_make(tmp_path):
    page = tmp_path / "page.md"
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks/sandbox_cost.py"), "--quick", "--repeats", "1",
         "--page", str(page)],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    rows = [line.split(" | ")[0] for line in page.read_text().splitlines() if line[:2] == "| "]
    kinds = ["bubblewrap", "chroot"] if AS_ROOT else ["bubblewrap"]
    expected = ["| what", "| bare", *kinds, *(f"| test, {k}" for k in kinds)]
    expected = [e if e.startswith("| ") else f"| {e}" for e in expected]
    assert rows == expected + (["| copy the submission"] if AS_ROOT else [])

"""The sandbox without namespaces (raykit_grading.sandbox.confine): the container's limits read
from its cgroups, the chroot tree that setup.sh builds."""

from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import AS_ROOT, REPO
from raykit_grading.sandbox.confine import ContainerLimits, container_limits


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

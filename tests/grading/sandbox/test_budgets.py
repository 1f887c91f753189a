"""What the grader counts of a running test (raykit_grading.sandbox.budgets), on a process of the
test's own here: each count against what the process really holds, each bound met at once. What
it reads of the archive a test returns is test_returned.py's."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from raykit_grading.sandbox.base import Limits
from raykit_grading.sandbox.budgets import (
    ContainerMemory,
    Watch,
    descendant,
    nameless_bytes,
    process_memory,
)
from raykit_grading.sandbox.leftovers import DiskBudget

MB = 2**20

HOLDER = """
import ctypes, os, sys, tempfile, time
libc = ctypes.CDLL(None, use_errno=True)
libc.mmap.restype = ctypes.c_void_p
libc.mmap.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int, ctypes.c_int, ctypes.c_int,
                      ctypes.c_long]
folder = sys.argv[1]
fd = os.open(folder, os.O_TMPFILE | os.O_RDWR, 0o600)  # no name, held by its descriptor
os.write(fd, b"x" * (3 * 2**20))
handle, name = tempfile.mkstemp(dir=folder)  # unlinked while open
os.write(handle, b"y" * (2 * 2**20))
os.unlink(name)
mapped, name = tempfile.mkstemp(dir=folder)  # held by a mapping alone
os.write(mapped, b"z" * 4096)
assert libc.mmap(None, 4096, 3, 0x01, mapped, 0) not in (None, 2**64 - 1)  # MAP_SHARED
os.close(mapped)
os.unlink(name)
named = os.open(os.path.join(folder, "named"), os.O_CREAT | os.O_WRONLY)  # a name: not counted
os.write(named, b"n" * 2**20)
for i in range(int(sys.argv[2])):  # two pages across a gigabyte boundary: page tables
    libc.mmap(0x100000000000 + (i << 30) - 4096, 8192, 3, 0x22 | 0x100000 | 0x8000, -1, 0)
os.fsync(fd)
print("ready", flush=True)
time.sleep(30)
"""


@pytest.fixture
def holder(tmp_path):
    """A process holding 3 MB and 2 MB in files with no name through descriptors, a page of
    one through a mapping alone, a named file of 1 MB, and (second call) page tables."""
    started = []

    def start(mappings: int = 0) -> subprocess.Popen:
        folder = tmp_path / f"tmp{len(started)}"
        folder.mkdir()
        process = subprocess.Popen(
            [sys.executable, "-c", HOLDER, str(folder), str(mappings)],
            stdout=subprocess.PIPE, text=True,
        )  # fmt: skip
        started.append(process)
        assert process.stdout.readline() == "ready\n"
        return process

    yield start
    for process in started:
        process.kill()
        process.wait()


def test_files_with_no_name_are_counted_through_descriptors_and_mappings(holder, tmp_path):
    process = holder()
    device = os.stat(tmp_path).st_dev
    held = nameless_bytes(process.pid, device, 64 * MB)
    assert held == 3 * MB + 2 * MB + 64 * MB  # the mapped one counts as a whole file may
    assert nameless_bytes(process.pid, device + 1, 64 * MB) == 0  # another disk: not the test's


def test_a_watch_stops_a_test_whose_files_with_no_name_pass_its_disk_budget(holder, tmp_path):
    process = holder()
    limits = Limits(disk=DiskBudget(bytes=16 * MB))
    watch = Watch(limits, None, process.pid, 0, tmp_path / "tmp0", None)
    said = watch()
    assert said.startswith("your code used more disk than allowed: it wrote more than 16 MB")
    assert "(69 MB of it in files with no name)" in said
    watch.maps_due = float("inf")  # the mappings not read again: what they held still counts
    assert "(69 MB of it in files with no name)" in watch.disk()
    within = Limits(disk=DiskBudget(bytes=128 * MB))
    assert Watch(within, None, process.pid, 0, tmp_path / "tmp0", None)() == ""


def test_memory_is_counted_with_the_page_tables_the_address_space_limit_does_not_bound(holder):
    plain, spread = holder(), holder(4000)
    extra = process_memory(spread.pid) - process_memory(plain.pid)
    assert extra >= 4000 * (8192 + 2 * 4096)  # its pages, and 2 page-table pages a mapping
    said = Watch(Limits(memory_bytes=process_memory(plain.pid) + 16 * MB), None, spread.pid, 0,
                 Path("/nonexistent"), None)()  # fmt: skip
    assert said.startswith("your code used more memory than allowed: its memory and page tables")
    assert process_memory(2**22 + 7) is None  # no such process


def test_the_test_process_is_found_below_the_one_the_sandbox_started():
    child = "import time; print('started', flush=True); time.sleep(30)"
    parent = subprocess.Popen(
        [sys.executable, "-c", f"import subprocess, sys; subprocess.run([sys.executable, '-c', "
         f"{child!r}])"],
        stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        assert parent.stdout.readline() == "started\n"  # the child has forked and exec'd
        found = descendant(parent.pid, 1)
        assert b"started" in Path(f"/proc/{found}/cmdline").read_bytes()
        assert descendant(parent.pid, 0) == parent.pid and descendant(parent.pid, 3) is None
    finally:
        parent.kill()
        parent.wait()


@pytest.mark.parametrize("v2", [False, True])
def test_the_containers_memory_less_its_file_cache_and_its_oom_kills(tmp_path, v2):
    prefix = "" if v2 else "total_"
    (tmp_path / ("memory.current" if v2 else "memory.usage_in_bytes")).write_text(f"{760 * MB}\n")
    (tmp_path / "memory.stat").write_text(
        f"anon {660 * MB}\n{prefix}active_file {60 * MB}\n{prefix}inactive_file {40 * MB}\n"
    )
    events = "memory.events" if v2 else "memory.oom_control"
    (tmp_path / events).write_text("oom_kill_disable 0\nunder_oom 0\noom_kill 3\n")
    container = ContainerMemory(tmp_path, 768 * MB, v2)
    assert container.held() == 660 * MB and container.oom_kills() == 3
    said = Watch(Limits(), container, 2**22 + 7, 0, tmp_path / "none", None)()
    assert said == ""  # 660 of 768 MB held, the file cache apart: within
    (tmp_path / "memory.stat").write_text(f"{prefix}inactive_file {MB}\n")
    said = Watch(Limits(), container, 2**22 + 7, 0, tmp_path / "none", None)()  # 759 MB held
    assert said.startswith("your code used more memory than allowed: the container's memory")
    assert ContainerMemory(tmp_path / "gone", 768 * MB, v2).held() is None


def test_the_graders_peak_is_its_own_not_that_of_the_process_that_started_it():
    """Linux carries ru_maxrss across exec: a grader started by a large process (a test
    runner's worker, a batch) must not report that process's resident set as its own."""
    launcher = bytearray(300 * 2**20)
    launcher[::4096] = b"\x01" * len(launcher[::4096])  # every page resident
    peak = "from raykit_grading.sandbox.budgets import grader_peak; print(grader_peak())"
    run = subprocess.run(
        [sys.executable, "-c", peak],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    assert int(run.stdout) < 200 * 2**20, (int(run.stdout) >> 20, len(launcher))

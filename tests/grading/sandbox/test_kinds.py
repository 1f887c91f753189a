"""Which kind of sandbox grades here (raykit_grading.sandbox.kinds): none, in one line, for a
normal user without namespaces; the benchmark times every kind this user can make."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from conftest import AS_ROOT, REPO

NOBODY = 65534


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


@pytest.mark.parametrize("kind", ["bubblewrap", "chroot"])
def test_the_preflight_probe_is_not_held_to_a_tests_wall_time(kind, tmp_path, child_python):
    """The probe (Python imports numpy and Pillow) runs only the grader's code: it gets
    PROBE_SECONDS, so a wall time shorter than Python's start, or a loaded machine, makes tests
    time out rather than the grader refuse to grade; the test after it is held to its wall."""
    from raykit_grading.grading.submissions import stage
    from raykit_grading.sandbox.base import Limits
    from raykit_grading.sandbox.kinds import KINDS
    from raykit_grading.sandbox.workspace import Workspace

    if kind == "chroot" and not AS_ROOT:
        pytest.skip("a chroot sandbox needs root")
    submitted = tmp_path / "submitted/raykit"
    submitted.mkdir(parents=True)
    (submitted / "__init__.py").write_text("")
    with Workspace(tmp_path) as workspace:
        staged = stage(submitted.parent, workspace / "submission")
        box = KINDS[kind](staged.root, workspace, child_python, Limits(wall_seconds=0.001))
        if kind == "bubblewrap" and shutil.which("bwrap") is None:
            pytest.skip("bubblewrap is not installed")
        box.check()  # raised IsolationUnavailable ("took longer than 0.001 s") before
        ran = box.run("probe", {}, {})
    assert ran.outputs is None and "took longer than 0.001 s" in ran.problem, ran.problem

"""Grading as deployed, in the five ways of the hostile suite (the package's docstring
says each), and reading what came back."""

from __future__ import annotations

import fcntl
import functools
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from conftest import REPO
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS
from raykit_grading.sandbox.confine import TREES

AS_ROOT = os.geteuid() == 0
WALL = 4.0
NOBODY = 65534
EMULATION = REPO / "tests" / "support" / "docker_confinement.py"
DEPLOYMENTS = ("root", "docker", "user", "container", "prairielearn")
POINTS = {t.key: t.points for t in TESTS}
SEED = 20261123
CONTAINERS: list[str] = []  # the container way's containers, each to be gone after its grading


def deployment_skip(way: str) -> str | None:
    """Why ``way`` cannot run on this machine, or None."""
    if way in ("root", "docker") and not AS_ROOT:
        return f"the {way} way runs run_autograder as root, as Gradescope does"
    if way == "docker":
        probe = subprocess.run(
            [sys.executable, str(EMULATION), "--memory-mb", "768", "--", "true"],
            capture_output=True, text=True,
        )  # fmt: skip
        if probe.returncode != 0:
            return f"cannot emulate Docker's confinement here: {probe.stderr.strip()}"
    if way == "user" and AS_ROOT and shutil.which("setpriv") is None:
        return "as root, the user way needs setpriv to become uid 65534"
    if way in ("container", "prairielearn"):
        from raykit_grading.platforms.containers import docker_problem

        problem = docker_problem()
        if problem:
            return f"the {way} way needs Docker: {problem}"
    return None


def _base_image_or_skip(say) -> str:
    from raykit_grading.platforms import containers

    base = os.environ.get("RAYKIT_CONTAINER_BASE", containers.DEBIAN_BASE)
    if not containers.image_exists(base):
        if base != containers.DEBIAN_BASE or not AS_ROOT:
            pytest.skip(f"no base image {base} (as root: python -m "
                        "raykit_grading.platforms.containers base-image)")  # fmt: skip
        try:
            containers.make_base_image(base, log=say)
        except containers.ContainerError as exc:
            pytest.skip(f"cannot make the base image {base}: {exc}")
    return base


def prairielearn_image(out: Path, say) -> str:
    """The image of the build folder ``prairielearn -o`` wrote in ``out`` (built once, then
    reused while the folder's contents are the same), on the container way's base."""
    from raykit_grading.platforms import containers

    base = _base_image_or_skip(say)
    try:
        built = containers.build_folder_image(out / "grader-image", base)
    except containers.ContainerError as exc:
        pytest.fail(f"the PrairieLearn grader image does not build: {exc}")
    how = "reused (same folder)" if built.cached else f"built in {built.seconds:.0f} s"
    say(f"prairielearn way: the grader image {built.image} on {base}: {how}")
    return built.image


def container_image(folder: Path, archive: Path, say) -> str:
    """The image Gradescope would build from ``archive`` (built once, then reused while the
    zip's contents are the same), on ``RAYKIT_CONTAINER_BASE`` (default the Debian base image,
    made with debootstrap if missing: skips saying why where it cannot be). A zip whose image
    does not build fails, as it would on Gradescope."""
    from raykit_grading.platforms import containers

    base = _base_image_or_skip(say)
    try:
        built = containers.build_image(archive, base, log_dir=Path(tempfile.gettempdir()))
    except containers.ContainerError as exc:
        pytest.fail(f"the zip's image does not build, so it would not on Gradescope: {exc}")
    how = "reused (same zip)" if built.cached else f"built in {built.seconds:.0f} s ({built.log})"
    say(f"container way: the zip's image {built.image} on {base}: {how}")
    return built.image


def way(autograder: Path) -> str:
    return autograder.name.rsplit("-", 1)[1]


# Each defence is paid for once in each way that differs in it. The docker way emulates, where
# Docker cannot run, the confinement the container way gives for real (the chroot sandbox in
# 768 MB, as Gradescope runs it): where the container way runs, the emulation would test the same
# defences twice, but for those that read the container's memory and its OOM kills, which the
# emulation gives the grader its own way (EMULATION_DIFFERS). The prairielearn way grades in
# that same sandbox in a container, and differs in its wiring and its limits (/grade,
# results.json's shape, a hidden test in one line, a submission not gradable, its memory and
# time, its containers removed): it runs the tests of those.
PRAIRIELEARN_DIFFERS = frozenset({
    "test_a_correct_submission_scores_full_marks_as_deployed",
    "test_2_a_raykit_that_is_a_link_to_the_reference_scores_zero",
    "test_5_a_hidden_tests_error_message_is_not_shown",
    "test_7_forged_results_and_a_killed_parent_change_nothing",
    "test_9_no_namespace_of_its_own_so_no_memory_beyond_its_limits",
    "test_9_no_gigabyte_held_by_the_kernel_outside_the_memory_limit",
    "test_a_slow_submission_is_stopped_by_the_total_budget",
    "test_11_every_budget_holds_and_hidden_outcomes_stay_hidden",
    "test_nothing_is_left_behind",
})  # fmt: skip


EMULATION_DIFFERS = frozenset({
    "test_a_correct_submission_scores_full_marks_as_deployed",
    "test_9_no_namespace_of_its_own_so_no_memory_beyond_its_limits",
    "test_9_no_gigabyte_held_by_the_kernel_outside_the_memory_limit",
    "test_11_every_budget_holds_and_hidden_outcomes_stay_hidden",
})  # fmt: skip


@functools.cache
def container_way_runs() -> bool:
    """Whether the container way grades on this machine (Docker and the base image there)."""
    from raykit_grading.platforms import containers

    base = os.environ.get("RAYKIT_CONTAINER_BASE", containers.DEBIAN_BASE)
    return deployment_skip("container") is None and containers.image_exists(base)


def grade_as_deployed(
    autograder: Path,
    submission: Path,
    only: list[str],
    tmp_path: Path,
    extra: str = "",
    wall: float | None = WALL,
) -> tuple[dict, subprocess.CompletedProcess]:
    """Grade the way an instructor does (see the module's docstring). ``wall``: each test's
    wall seconds (:data:`WALL`, so that an attack that holds its test costs little), or None
    for each test's own, as deployed: an honest submission's renders may take longer than
    WALL on a loaded machine, and its full marks must not depend on the load."""
    from grader_python import grader_python

    python = grader_python()[0]
    walls = "" if wall is None else f"--wall-seconds {wall} "
    options = f"--only {' '.join(only)} {walls}--seed {SEED} {extra}"
    if way(autograder) == "container":
        return _grade_in_a_container(autograder, submission, options, tmp_path)
    if way(autograder) == "prairielearn":
        return _grade_as_prairielearn(autograder, submission, options, only, tmp_path)
    if way(autograder) in ("root", "docker"):
        shutil.rmtree(autograder / "submission", ignore_errors=True)
        shutil.rmtree(autograder / "results", ignore_errors=True)
        subprocess.run(["cp", "-a", str(submission), str(autograder / "submission")], check=True)
        env = {
            "PATH": "/usr/bin:/bin",
            "AUTOGRADER_ROOT": str(autograder),
            "RAYKIT_GRADER_PYTHON": python,
            "RAYKIT_GRADE_OPTIONS": options,
        }
        command = ["bash", str(autograder / "run_autograder")]
        if way(autograder) == "docker":
            command = [sys.executable, str(EMULATION), "--memory-mb", "768", "--", *command]
        run = subprocess.run(command, env=env, capture_output=True, text=True, timeout=300)
        path = autograder / "results/results.json"
        expected_sandbox = "bubblewrap" if way(autograder) == "root" else "chroot+uid+"
    elif not AS_ROOT:
        path = tmp_path / "results" / "results.json"
        run = subprocess.run(
            [sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o", str(path),
             *options.split()],
            capture_output=True, text=True, timeout=300, cwd=REPO,
        )  # fmt: skip
        expected_sandbox = "bubblewrap"
    else:  # as root: uid 65534, in a folder of its own
        folder = Path(tempfile.mkdtemp(prefix="raykit-user-", dir="/tmp"))
        try:
            subprocess.run(["cp", "-a", str(submission), str(folder / "submission")], check=True)
            subprocess.run(["chown", "-R", f"{NOBODY}:{NOBODY}", str(folder)], check=True)
            path = folder / "results" / "results.json"
            run = subprocess.run(
                ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups",
                 python, "-m", "raykit_grading", "grade", str(folder / "submission"),
                 "-o", str(path), *options.split()],
                capture_output=True, text=True, timeout=300, cwd=REPO,
                env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(REPO), "TMPDIR": str(folder)},
            )  # fmt: skip
            results = json.loads(path.read_text())
            left = [p.name for p in folder.glob("raykit-grading-*")]  # its TMPDIR
            assert left == [], f"the grader left {left}"
        finally:
            shutil.rmtree(folder, ignore_errors=True)
        assert results["extra_data"]["sandbox"] in (
            "bubblewrap",
            "none: nothing of the submission was run",
        ), results["extra_data"]
        return results, run
    results = json.loads(path.read_text())
    _assert_sandbox(results, expected_sandbox, run.stderr)
    return results, run


def _assert_sandbox(results: dict, expected: str, said: str) -> None:
    """The grading ran in the ``expected`` kind of sandbox (or ran nothing of the submission);
    where the grader could not grade, the message says why, in its words and its last lines."""
    sandbox = results["extra_data"].get("sandbox", "")
    assert sandbox.startswith(expected) or sandbox.startswith("none"), (
        f"sandbox {sandbox!r}; not graded: {results['extra_data'].get('not_graded')}\n"
        f"{said[-3000:]}"
    )


def _grade_in_a_container(
    autograder: Path, submission: Path, options: str, tmp_path: Path
) -> tuple[dict, subprocess.CompletedProcess]:
    """A fresh container of the zip's image grades ``submission``, as on Gradescope; the
    options reach ``run_autograder`` as ``RAYKIT_GRADE_OPTIONS`` (``docker create -e``)."""
    from raykit_grading.platforms.containers import grade_in_container

    image = (autograder / "image").read_text()
    graded = grade_in_container(
        image, submission, tmp_path / "container-results",
        env={"RAYKIT_GRADE_OPTIONS": options}, timeout=300,
    )  # fmt: skip
    CONTAINERS.append(graded.container)
    assert graded.results is not None, f"{graded.problem}:\n{graded.output[-3000:]}"
    _assert_sandbox(graded.results, "chroot+uid+", graded.output)
    run = subprocess.CompletedProcess(
        ["docker", "start", "--attach"], graded.status, graded.output, graded.output
    )
    return graded.results, run


def _grade_as_prairielearn(
    autograder: Path, submission: Path, options: str, only: list[str], tmp_path: Path
) -> tuple[dict, subprocess.CompletedProcess]:
    """A fresh container of the grader image grades ``submission`` as PrairieLearn runs it;
    the options reach the entrypoint as ``RAYKIT_GRADE_OPTIONS`` (``docker run -e``)."""
    from raykit_grading.platforms.containers import grade_in_prairielearn_container
    from raykit_grading.platforms.prairielearn import ENTRYPOINT, SUBMITTED_FILE

    entries = list(submission.iterdir())
    if len(entries) == 1 and entries[0].suffix == ".zip":  # uploaded as the question names it
        (tmp_path / "upload").mkdir()
        shutil.copy(entries[0], tmp_path / "upload" / SUBMITTED_FILE)
        submission = tmp_path / "upload"
    graded = grade_in_prairielearn_container(
        (autograder / "image").read_text(), submission, autograder / "tests",
        tmp_path / "prairielearn-results", ENTRYPOINT, 300,
        env={"RAYKIT_GRADE_OPTIONS": options},
    )  # fmt: skip
    CONTAINERS.append(graded.container)
    assert graded.results is not None, f"{graded.problem}:\n{graded.output[-3000:]}"
    results = as_gradescope(graded.results, only)
    _assert_sandbox(results, "chroot+uid+", graded.output)
    output = graded.output
    run = subprocess.CompletedProcess(["docker", "run"], graded.status, output, output)
    return results, run


def as_gradescope(learn: dict, only: list[str]) -> dict:
    """PrairieLearn's results in the shape the assertions read (Gradescope's): each test by
    number (the hidden tests' one line as ``hidden``); a submission PrairieLearn is not to
    count scores nothing on every test, its format errors as each test's output. The
    original is under ``prairielearn``."""
    if learn.get("gradable") is False:
        why = "\n".join(learn.get("format_errors", [])) or learn["message"]
        tests = [{"number": t.key, "score": 0, "max_score": t.points, "output": why,
                  "status": "failed"} for t in TESTS if t.key in only]  # fmt: skip
        extra = {"sandbox": "none: not gradable"}
    else:
        tests = [{"number": "hidden" if t["name"] == "Hidden tests" else t["name"].split()[0],
                  "score": t["points"], "max_score": t["max_points"],
                  "output": t["output"] or t["message"],
                  "status": "passed" if t["points"] >= t["max_points"] else "failed"}
                 for t in learn["tests"]]  # fmt: skip
        extra = learn.get("extra_data", {})
    return {"score": sum(t["score"] for t in tests), "output": learn["message"], "tests": tests,
            "extra_data": extra, "prairielearn": learn}  # fmt: skip


HIDDEN_KEYS = {t.key for t in TESTS if t.visibility != "visible"}


def shown(autograder: Path, expected: dict[str, float]) -> dict[str, float]:
    """Expected scores as the way shows them: on PrairieLearn the hidden tests are one line."""
    if way(autograder) != "prairielearn" or not HIDDEN_KEYS.intersection(expected):
        return expected
    hidden = sum(v for k, v in expected.items() if k in HIDDEN_KEYS)
    return {**{k: v for k, v in expected.items() if k not in HIDDEN_KEYS}, "hidden": hidden}


def submission_with(release: Path, tmp_path: Path, edits: dict[str, str], **fmt) -> Path:
    """The solution with code appended to some of its modules."""
    folder = make_submission(tmp_path / "submission")
    for name, code in edits.items():
        with open(folder / "raykit" / name, "a") as module:
            module.write("\n" + code.format(**fmt) + "\n")
    return folder


def submission_wrapping(tmp_path: Path, wrappers: dict[str, tuple[str, str]]) -> Path:
    """The solution with functions wrapped, ``{module: (function, code)}``: the original is
    renamed ``_function`` and ``code`` defines ``function`` anew (calling the original)."""
    folder = make_submission(tmp_path / "submission")
    for name, (function, code) in wrappers.items():
        path = folder / "raykit" / name
        text = path.read_text().replace(f"def {function}(", f"def _{function}(", 1)
        path.write_text(text + "\n" + code)
    return folder


def processes_naming(marker: str) -> list[str]:
    """The pids of this machine's processes whose command line holds ``marker``. A command line
    is bytes, read as bytes: another test's may name a file whose name is not UTF-8."""
    found = []
    for proc in Path("/proc").iterdir():
        try:
            if proc.name.isdigit() and marker.encode() in (proc / "cmdline").read_bytes():
                found.append(proc.name)
        except OSError:
            pass
    return found


def scores(results: dict) -> dict[str, float]:
    return {t["number"]: t["score"] for t in results["tests"]}


def everything_visible(results: dict) -> str:
    return json.dumps(results)


def leftovers_no_grader_holds() -> list[str]:
    """What no running grader holds: test folders' contents in the chroot trees' slots,
    graders' workspaces, the quarantines."""
    found = []
    for slot in TREES.glob("tree-*/tasks/*") if AS_ROOT else ():
        lock = TREES / f".slots-{slot.parent.parent.name}" / slot.name
        if not held_by_a_grader(lock):
            found += [str(p) for p in slot.iterdir()]
    for quarantine in [
        TREES / "quarantine",
        Path(tempfile.gettempdir()) / "raykit-grading-quarantine",
    ]:
        if quarantine.is_dir():
            found += [str(p) for p in quarantine.iterdir()]
    for folder in Path(tempfile.gettempdir()).glob("raykit-grading-*"):
        if folder.name != "raykit-grading-quarantine" and not held_by_a_grader(folder / ".lock"):
            found.append(str(folder))
    return found


def sandbox_processes_no_grader_holds(looks: int = 3, pause: float = 1.0) -> list[str]:
    """The pids of processes of a sandbox uid whose uid no running grader holds, found at each
    of ``looks`` looks ``pause`` seconds apart. A grader on another worker may end between
    reading a process's uid and reading its lock, killing the process and giving back its uid
    meanwhile; a process left behind is still there at every look."""
    from raykit_grading.sandbox.isolation import SANDBOX_UIDS, UID_LOCKS

    def unheld() -> set[str]:
        found = set()
        for proc in Path("/proc").iterdir():
            if not proc.name.isdigit():
                continue
            try:
                uid = proc.stat().st_uid
                if uid in SANDBOX_UIDS and not held_by_a_grader(UID_LOCKS / str(uid)):
                    if proc.stat().st_uid == uid:  # still there, its uid free
                        found.add(proc.name)
            except FileNotFoundError:  # a process of this machine that ended meanwhile
                continue
        return found

    left = unheld()
    for _ in range(looks - 1):
        if not left:
            break
        time.sleep(pause)
        left &= unheld()
    return sorted(left, key=int)


def held_by_a_grader(lock: Path) -> bool:
    """Whether a live grader holds ``lock`` (other graders may be running on this machine:
    only what none of them holds was left behind)."""
    try:
        fd = os.open(lock, os.O_RDONLY)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        return False
    except BlockingIOError:
        return True
    finally:
        os.close(fd)

"""Hostile submissions, graded end to end by the real grader: each gets exactly the score it
deserves, nothing outside its sandbox is read or written, and results.json is always valid
and the grader's own.

Every test that grades through :func:`grade_as_deployed` runs in the five ways below (the
``autograder`` fixture's parameter), each skipped with its reason where this machine cannot make
it, or where another way already tests the same defences (:func:`each_defence_once`: the docker
way where the container way runs, but for :data:`EMULATION_DIFFERS`; the prairielearn way but
for :data:`PRAIRIELEARN_DIFFERS`):

* ``root``: the autograder zip's own ``run_autograder`` as root, the zip unpacked as
  Gradescope does (into ``source/``, ``run_autograder`` copied beside it, ``source/`` closed to
  everyone but root), run by a grader Python with only what ``setup.sh`` installs
  (tests/support/grader_python.py): bubblewrap's sandbox;
* ``docker``: the same ``run_autograder`` as root under an emulation of Docker's default
  confinement with a 768 MB memory limit (``tests/support/docker_confinement.py``), as
  Gradescope runs it: no namespaces, so the chroot sandbox (:mod:`raykit_grading.confine`);
* ``user``: the README's ``python -m raykit_grading grade`` as a normal user (this one, or as
  root ``setpriv`` to uid 65534 with the same grader Python, which that uid can run);
* ``container``: the zip in a real Docker container, as Gradescope builds and runs it
  (:mod:`raykit_grading.containers`): an image built once per session from the zip on a base
  image (``RAYKIT_CONTAINER_BASE``, default the Debian one made with debootstrap, made here if
  missing), ``setup.sh`` run at build time, then a fresh container per submission with
  Docker's default seccomp profile and capabilities, 768 MB and half a CPU, the submission
  copied to ``/autograder/submission``, ``/autograder/run_autograder`` as the command: the
  chroot sandbox, for real. Skipped, saying why, where Docker cannot run containers.
* ``prairielearn``: the grader image whose build folder ``prairielearn -o`` writes
  (:mod:`raykit_grading.prairielearn`), built once per session on the same base, run as
  PrairieLearn's grader host runs it (``containers.grade_in_prairielearn_container``):
  ``/grade`` laid out as its docs say (the submission's files in ``/grade/student``, as a
  workspace question's ``gradedFiles`` sends a ``raykit/`` folder; the question's ``tests/``
  with the seed and hidden scenes), no network, its limits, the entrypoint info.json names.
  Its results.json is read back into Gradescope's shape for the same assertions
  (:func:`as_gradescope`): hidden tests are one line there (:func:`shown` says what a test's
  expected scores look like that way), and a submission that is not gradable scores nothing.

The batch tests run as the user running the suite, but for
:func:`test_11_a_batch_grades_honest_students_between_attackers_in_full`, which runs ``batch``
in each way it runs on an instructor's machine (:data:`BATCH_WAYS`). Every attack that needs
something outside its sandbox has a way to profit if it got it (it then answers right and
scores), so a defence that failed shows as a score above the one asserted.

Kinds (numbers as in the trust issue): 1 hard-coding the shipped answers, 2 links and special
files in the submission, 3 child-controlled output, 4 one broken test, 5 hidden inputs reaching
visible output, 6 reading the solution from disk, 7 forging results and killing the grader,
8 no usable child Python, 9 classmates, the network, outliving the test, 10 what one test
leaves, 11 everything a test can hold, and what is shown at once of hidden tests (issue 56:
tests/support/budget_attacks.py); and the old ones: loops, memory, forks, printing,
monkeypatching, garbage arrays.
"""

from __future__ import annotations

import csv
import fcntl
import functools
import html
import json
import os
import platform
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import zipfile
from pathlib import Path

import numpy as np
import pytest
from budget_attacks import budget_attacker

from conftest import REPO
from mistaken_submissions import make_submission
from raykit_grading.autograder import build_zip
from raykit_grading.catalog import TESTS
from raykit_grading.confine import TREES

pytestmark = pytest.mark.slow

AS_ROOT = os.geteuid() == 0
WALL = 4.0
NOBODY = 65534
EMULATION = REPO / "tests" / "support" / "docker_confinement.py"
DEPLOYMENTS = ("root", "docker", "user", "container", "prairielearn")
POINTS = {t.key: t.points for t in TESTS}
SEED = 20261123
CONTAINERS: list[str] = []  # the container way's containers, each to be gone after its grading


@pytest.fixture(scope="module")
def canary(tmp_path_factory):
    """A world-readable secret outside every sandbox (as an instructor's checkout is)."""
    folder = Path("/tmp") / f"raykit-canary-{os.getpid()}"
    folder.mkdir(exist_ok=True)
    os.chmod(folder, 0o755)
    secret = folder / "secret.txt"
    secret.write_text("CANARY-7f3a: the hidden answers\n")
    os.chmod(secret, 0o644)
    yield secret
    shutil.rmtree(folder, ignore_errors=True)


def _deployment_skip(way: str) -> str | None:
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
        from raykit_grading.containers import docker_problem

        problem = docker_problem()
        if problem:
            return f"the {way} way needs Docker: {problem}"
    return None


def _base_image_or_skip(say) -> str:
    from raykit_grading import containers

    base = os.environ.get("RAYKIT_CONTAINER_BASE", containers.DEBIAN_BASE)
    if not containers.image_exists(base):
        if base != containers.DEBIAN_BASE or not AS_ROOT:
            pytest.skip(f"no base image {base} (as root: python -m raykit_grading.containers "
                        "base-image)")  # fmt: skip
        try:
            containers.make_base_image(base, log=say)
        except containers.ContainerError as exc:
            pytest.skip(f"cannot make the base image {base}: {exc}")
    return base


def prairielearn_image(out: Path, say) -> str:
    """The image of the build folder ``prairielearn -o`` wrote in ``out`` (built once, then
    reused while the folder's contents are the same), on the container way's base."""
    from raykit_grading import containers

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
    from raykit_grading import containers

    base = _base_image_or_skip(say)
    try:
        built = containers.build_image(archive, base, log_dir=Path(tempfile.gettempdir()))
    except containers.ContainerError as exc:
        pytest.fail(f"the zip's image does not build, so it would not on Gradescope: {exc}")
    how = "reused (same zip)" if built.cached else f"built in {built.seconds:.0f} s ({built.log})"
    say(f"container way: the zip's image {built.image} on {base}: {how}")
    return built.image


@pytest.fixture(scope="module", params=DEPLOYMENTS)
def autograder(request, tmp_path_factory, grader_python):
    """The autograder zip unpacked as Gradescope does (into ``source/``, ``run_autograder``
    copied from there beside it), source closed to everyone but root; its folder's name ends in
    the way it is graded (:data:`DEPLOYMENTS`)."""
    why = _deployment_skip(request.param)
    if why:
        pytest.skip(why)
    root = Path("/tmp") / f"raykit-autograder-{os.getpid()}-{request.param}"
    shutil.rmtree(root, ignore_errors=True)
    (root / "source").mkdir(parents=True)
    if request.param in ("container", "prairielearn"):  # a fixed seed: the same image
        plugins = request.config.pluginmanager
        reporter, capture = (
            plugins.get_plugin("terminalreporter"),
            plugins.get_plugin("capturemanager"),
        )

        def say(line: str) -> None:  # in CI's log, past pytest's capture
            if reporter is None or capture is None:
                return print(line)
            with capture.global_and_fixture_disabled():
                reporter.write_line(line)

        if request.param == "prairielearn":
            from raykit_grading.prairielearn import write_course_files

            out = write_course_files(root / "course", "course/raykit", SEED)
            (root / "image").write_text(prairielearn_image(out, say))
            shutil.copytree(out / "questions/raykit/tests", root / "tests")
        else:
            archive = build_zip(tmp_path_factory.mktemp("zip") / "autograder.zip", SEED)
            (root / "image").write_text(container_image(root, archive, say))
        yield root
        shutil.rmtree(root, ignore_errors=True)
        return
    archive = build_zip(tmp_path_factory.mktemp("zip") / "autograder.zip")
    with zipfile.ZipFile(archive) as opened:
        opened.extractall(root / "source")
    shutil.copy(root / "source/run_autograder", root / "run_autograder")
    os.chmod(root, 0o755)
    os.chmod(root / "source", 0o700)
    yield root
    shutil.rmtree(root, ignore_errors=True)


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
    from raykit_grading import containers

    base = os.environ.get("RAYKIT_CONTAINER_BASE", containers.DEBIAN_BASE)
    return _deployment_skip("container") is None and containers.image_exists(base)


@pytest.fixture(autouse=True)
def each_defence_once(request):
    """Skips, saying why, a way that would test again defences another way tests."""
    params = getattr(request.node, "callspec", None)
    deployed = params.params.get("autograder") if params else None
    if (
        deployed == "docker"
        and request.node.originalname not in EMULATION_DIFFERS
        and container_way_runs()
    ):
        pytest.skip("the container way tests this confinement for real on this machine")
    if deployed == "prairielearn" and request.node.originalname not in PRAIRIELEARN_DIFFERS:
        pytest.skip("the prairielearn way meets this attack in the container way's sandbox")


def grade_as_deployed(
    autograder: Path, submission: Path, only: list[str], tmp_path: Path, extra: str = ""
) -> tuple[dict, subprocess.CompletedProcess]:
    """Grade the way an instructor does (see the module's docstring)."""
    from grader_python import grader_python

    python = grader_python()[0]
    options = f"--only {' '.join(only)} --wall-seconds {WALL} --seed {SEED} {extra}"
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
    sandbox = results["extra_data"].get("sandbox", "")
    assert sandbox.startswith(expected_sandbox) or sandbox.startswith("none"), sandbox
    return results, run


def _grade_in_a_container(
    autograder: Path, submission: Path, options: str, tmp_path: Path
) -> tuple[dict, subprocess.CompletedProcess]:
    """A fresh container of the zip's image grades ``submission``, as on Gradescope; the
    options reach ``run_autograder`` as ``RAYKIT_GRADE_OPTIONS`` (``docker create -e``)."""
    from raykit_grading.containers import grade_in_container

    image = (autograder / "image").read_text()
    graded = grade_in_container(
        image, submission, tmp_path / "container-results",
        env={"RAYKIT_GRADE_OPTIONS": options}, timeout=300,
    )  # fmt: skip
    CONTAINERS.append(graded.container)
    assert graded.results is not None, f"{graded.problem}:\n{graded.output[-3000:]}"
    sandbox = graded.results["extra_data"].get("sandbox", "")
    assert sandbox.startswith("chroot+uid+") or sandbox.startswith("none"), sandbox
    run = subprocess.CompletedProcess(
        ["docker", "start", "--attach"], graded.status, graded.output, graded.output
    )
    return graded.results, run


def _grade_as_prairielearn(
    autograder: Path, submission: Path, options: str, only: list[str], tmp_path: Path
) -> tuple[dict, subprocess.CompletedProcess]:
    """A fresh container of the grader image grades ``submission`` as PrairieLearn runs it;
    the options reach the entrypoint as ``RAYKIT_GRADE_OPTIONS`` (``docker run -e``)."""
    from raykit_grading.containers import grade_in_prairielearn_container
    from raykit_grading.prairielearn import ENTRYPOINT, SUBMITTED_FILE

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
    sandbox = results["extra_data"].get("sandbox", "")
    assert sandbox.startswith("chroot+uid+") or sandbox.startswith("none"), sandbox
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
    """The pids of this machine's processes whose command line holds ``marker``."""
    found = []
    for proc in Path("/proc").iterdir():
        try:
            if proc.name.isdigit() and marker in (proc / "cmdline").read_text():
                found.append(proc.name)
        except OSError:
            pass
    return found


def scores(results: dict) -> dict[str, float]:
    return {t["number"]: t["score"] for t in results["tests"]}


def everything_visible(results: dict) -> str:
    return json.dumps(results)


# ---- the old kinds: each scores 0 on the tests it sabotages, and the run survives ----------

SABOTAGE = {
    "infinite loop at import": ("__init__.py", "while True:\n    pass"),
    "memory bomb": ("__init__.py", "hog = [bytearray(10**8) for _ in range(1000)]"),
    "fork bomb": (
        "__init__.py",
        "import os\nwhile True:\n    try:\n        os.fork()\n    except OSError:\n        pass",
    ),
    "os._exit at import": ("__init__.py", "import os\nos._exit(0)"),
    "prints 100 MB": (
        "__init__.py",
        "import sys\nfor _ in range(100):\n    sys.stdout.write('x' * 1_000_000)\n"
        "sys.stdout.flush()",
    ),
    "monkeypatches numpy and the comparison": (
        "planes.py",
        "import numpy as _np\n_np.allclose = _np.isclose = _np.array_equal = "
        "lambda *a, **k: True\nimport sys as _sys\n_sys.modules['raykit_grading'] = None\n"
        "def hit_plane(origins, directions, a, n):\n    return _np.zeros(len(origins))",
    ),
    "wrong shape": (
        "planes.py",
        "import numpy as _np\ndef hit_plane(origins, directions, a, n):\n    return _np.zeros(3)",
    ),
    "strings instead of numbers": (
        "planes.py",
        "import numpy as _np\ndef hit_plane(origins, directions, a, n):\n"
        "    return _np.array(['7'] * len(origins))",
    ),
    "NaN everywhere": (
        "render.py",
        "import numpy as _np\ndef render(scene, samples=1, **kw):\n"
        "    h, w = scene.camera.height, scene.camera.width\n"
        "    return Render(_np.full((h, w, 3), _np.nan), None, None)",
    ),
}


def test_a_process_left_holding_the_tests_output_costs_the_test_nothing(
    release, autograder, tmp_path
):
    """Importing raykit tries to start a process that would keep the test's output pipes
    open and sleep (a test is one process: the fork is refused, and the import goes on): the
    test is graded when its own code is done, not when pipes close, and no such process is
    left."""
    marker = f"HOLDER-{os.getpid()}"
    code = (
        "import os as _os, sys as _sys\n"
        "try:\n    _pid = _os.fork()\nexcept OSError:\n    _pid = -1\n"
        "if _pid == 0:\n"
        f"    _os.execv(_sys.executable, [_sys.executable, '-c', 'import time; time.sleep(60)', "
        f"'{marker}'])\n"
    )
    submission = submission_with(release, tmp_path, {"__init__.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": 2, "3.6": 4}, results
    assert processes_naming(marker) == []
    honest = make_submission(tmp_path / "honest" / "submission")  # the next student
    results, run = grade_as_deployed(autograder, honest, ["2.1", "3.6"], tmp_path / "honest")
    assert run.returncode == 0 and scores(results) == {"2.1": 2, "3.6": 4}, results


@pytest.mark.parametrize("name", sorted(SABOTAGE))
def test_sabotage_scores_zero_and_the_run_survives(name, release, autograder, tmp_path):
    file, code = SABOTAGE[name]
    submission = submission_with(release, tmp_path, {file: code})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    # the solution with one module sabotaged: what needs that module scores nothing
    expected = {"2.1": 2, "3.6": 0} if file == "render.py" else {"2.1": 0, "3.6": 0}
    if name == "prints 100 MB":  # printing is no mistake: the output is cut, the code graded
        expected = {"2.1": 2, "3.6": 4}
    assert scores(results) == expected, results
    text = [re.sub(r"<img [^>]*>", "", t["output"]) for t in results["tests"]]
    assert all(len(output) <= 5000 for output in text)  # the printing is cut


# ---- 1: the shipped (public) answers do not answer the graded tests --------------------------


def test_1_a_submission_that_replays_the_shipped_answers_scores_zero(release, autograder, tmp_path):
    """It implements nothing: it returns the release's expected results (and reference image)
    for any input, which passes every public test and no graded one."""
    submission = make_submission(tmp_path / "submission")
    answers = submission / "raykit" / "answers"
    for case in ("2_1", "3_6", "4_4"):
        shutil.copytree(release / "tests/expected" / case, answers / case)
    replay = (
        "import numpy as _np, pathlib as _p\n"
        "_A = _p.Path(__file__).parent / 'answers'\n"
        "def _answer(case, key):\n"
        "    with _np.load(_A / case / 'expected.npz') as data:\n"
        "        return data[key]\n"
    )
    edits = {
        "planes.py": replay + "def hit_plane(o, d, a, n):\n    return _answer('2_1', 't')",
        "shading.py": replay + "def lambert(kd, i, n, l):\n    return _answer('4_4', 'L')",
        "render.py": replay + "def render(scene, samples=1, **kw):\n"
        "    return Render(_answer('3_6', 'rgb'), None, None)",
    }
    for name, code in edits.items():
        with open(submission / "raykit" / name, "a") as module:
            module.write("\n" + code + "\n")
    nodes = [f"tests/test_visible.py::test_visible[{t.name}]" for t in TESTS
             if t.key in ("2.1", "3.6", "4.4")]  # fmt: skip
    student = subprocess.run(  # the public tests: all three pass
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *nodes],
        cwd=_release_with(release, submission, tmp_path), capture_output=True, text=True,
        env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(tmp_path / "with")},
    )  # fmt: skip
    assert "3 passed" in student.stdout, student.stdout[-1500:]
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6", "4.4"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": 0, "3.6": 0, "4.4": 0}, results


def _release_with(release: Path, submission: Path, tmp_path: Path) -> Path:
    folder = tmp_path / "with"
    shutil.copytree(release, folder)
    shutil.rmtree(folder / "raykit")
    shutil.copytree(submission / "raykit", folder / "raykit")
    return folder


# ---- 2: links and special files in the submission are never followed ------------------------


def test_2_a_raykit_that_is_a_link_to_the_reference_scores_zero(autograder, tmp_path):
    submission = tmp_path / "submission"
    submission.mkdir()
    (submission / "raykit").symlink_to(REPO / "raykit")
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert scores(results) == {"2.1": 0, "3.6": 0}
    assert "raykit is a symbolic link: not followed" in results["output"]
    assert "no raykit package" in results["tests"][0]["output"]
    if way(autograder) == "prairielearn":  # the wrong shape: not gradable, not a zero
        assert results["prairielearn"]["gradable"] is False
    assert run.returncode == 0  # graded (a zero, with the reason): exit 0, whatever the score


def test_2_linked_modules_fifos_and_zip_tricks_are_left_out(release, autograder, tmp_path):
    """planes.py a link to the reference's, a FIFO beside it: planes.py is missing, so every
    test that needs it fails; the FIFO is never opened (no hang)."""
    submission = make_submission(tmp_path / "submission")
    (submission / "raykit/planes.py").unlink()
    (submission / "raykit/planes.py").symlink_to(REPO / "raykit/planes.py")
    os.mkfifo(submission / "raykit/pipe.py")
    results, run = grade_as_deployed(autograder, submission, ["2.1", "2.3"], tmp_path)
    assert scores(results) == {"2.1": 0, "2.3": 2}, results
    assert "raykit/planes.py is a symbolic link: left out" in results["output"]
    assert "raykit/pipe.py is a named pipe (FIFO): left out" in results["output"]


def test_2_a_zipped_submission_is_unpacked_without_links_or_escapes(autograder, tmp_path):
    solution = make_submission(tmp_path / "solution")
    submission = tmp_path / "submission"
    submission.mkdir()
    with zipfile.ZipFile(submission / "work.zip", "w") as archive:
        for path in sorted((solution / "raykit").rglob("*.py")):
            archive.write(path, f"mine/{path.relative_to(solution)}")
        link = zipfile.ZipInfo("mine/raykit/evil.py")
        link.external_attr = 0o120777 << 16  # a symbolic link to the grader
        archive.writestr(link, "/autograder/source/raykit/planes.py")
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "evil.py is a link: left out" in results["output"]


# ---- 3: what the child hands back is read as untrusted -------------------------------------

RETURNED = {
    "a compressed npz (a bomb)": (
        "import io, zipfile\n"
        "buf = io.BytesIO()\n"
        "with zipfile.ZipFile(buf, 'w', zipfile.ZIP_DEFLATED) as z:\n"
        "    z.writestr('t.npy', b'\\x93NUMPY\\x01\\x00v\\x00' + b' ' * 118 + b'\\n'"
        " + b'\\0' * 50_000_000)\n"
        "data = buf.getvalue()"
    ),
    "a header that claims a huge array": (
        "import io, zipfile\n"
        "header = \"{{'descr': '<f8', 'fortran_order': False, 'shape': (10**12,), }}\"\n"
        "header = header.ljust(117) + '\\n'\n"
        "npy = b'\\x93NUMPY\\x01\\x00' + len(header).to_bytes(2, 'little') + header.encode()\n"
        "buf = io.BytesIO()\n"
        "with zipfile.ZipFile(buf, 'w') as z:\n"
        "    z.writestr('t.npy', npy + b'\\0' * 64)\n"
        "data = buf.getvalue()"
    ),
    "object arrays (pickles)": (
        "import io, numpy\nbuf = io.BytesIO()\n"
        "numpy.savez(buf, t=numpy.array([object()], dtype=object))\ndata = buf.getvalue()"
    ),
    "garbage": "data = b'PK' + b'\\xff' * 5000",
    "endless bytes": "data = b'x' * (200 * 2**20)",
}


@pytest.mark.parametrize("name", sorted(RETURNED))
def test_3_what_a_child_returns_is_checked_before_it_is_believed(
    name, release, autograder, tmp_path
):
    """The child writes its own 'results' to the grader's pipe (task.json names it) and exits
    before child.py can."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import json, os, sys\n"
        + "".join(f"    {line}\n" for line in RETURNED[name].splitlines())
        + "    order = json.load(open(os.path.join(sys.argv[1], 'task.json')))\n"
        "    out = open(order['outputs_fd'], 'wb', closefd=False)\n"
        "    out.write(data)\n    out.flush()\n    os._exit(0)"
    )
    submission = submission_with(release, tmp_path, {"planes.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "2.3"], tmp_path)
    assert scores(results) == {"2.1": 0, "2.3": 2}, results
    assert run.returncode == 0, run.stderr[-2000:]


def test_3_the_sandbox_gives_the_child_no_writable_path_the_grader_reads(
    release, autograder, tmp_path
):
    """It tries to swap every file of its work folder for a link to a root-only file or a
    FIFO: the folder is read-only, and the grader reads nothing back from it anyway."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os, numpy as np\n"
        "    swapped = 0\n"
        "    for name in os.listdir('/work'):\n"
        "        try:\n"
        "            os.replace('/work/' + name, '/tmp/x'); swapped += 1\n"
        "        except OSError:\n            pass\n"
        "        try:\n"
        "            os.mkfifo('/work/' + name + '.fifo'); swapped += 1\n"
        "        except OSError:\n            pass\n"
        "    return np.full(len(origins), np.inf) if swapped == 0 else 1 / 0"
    )
    submission = submission_with(release, tmp_path, {"planes.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert "division by zero" not in everything_visible(results)
    assert scores(results) == {"2.1": 0}


# ---- 4: one broken test is that test's alone -----------------------------------------------


def test_4_a_test_that_kills_its_own_child_costs_only_that_test(release, autograder, tmp_path):
    code = "def hit_plane(origins, directions, a, n):\n    import os\n    os._exit(3)"
    submission = submission_with(release, tmp_path, {"planes.py": code})
    only = ["2.1", "2.3", "3.1", "4.1"]
    results, run = grade_as_deployed(autograder, submission, only, tmp_path)
    assert scores(results) == {"2.1": 0, "2.3": 2, "3.1": 1, "4.1": 1}, results
    assert results["score"] == sum(POINTS[k] for k in only) - POINTS["2.1"]


# ---- 5: hidden inputs never reach a visible test's output ----------------------------------


def test_5_a_hidden_test_cannot_leave_its_inputs_for_a_visible_one(release, autograder, tmp_path):
    """The hidden ray-sphere tests (2.4, 2.5) hide their inputs everywhere they can write; the
    visible plane-side test (2.6) prints whatever it finds (it runs before them, as every
    visible test does: test_10_visible_tests_run_before_hidden_ones; the stashes would be gone
    in any order)."""
    stash = ["/tmp/stash", "/dev/shm/stash", "/var/tmp/stash", "/work/stash"]
    code = (
        "def hit_sphere(origins, directions, center, radius):\n    import os\n"
        f"    for path in {stash!r} + [os.path.expanduser('~/stash')]:\n"
        "        try:\n"
        "            open(path, 'w').write('HIDDEN-INPUTS ' + repr(center.tolist()))\n"
        "        except OSError:\n            pass\n"
        "    return _hit_sphere(origins, directions, center, radius)\n"
    )
    peek = (
        "def plane_side(p, a, n):\n    import os\n"
        f"    for path in {stash!r} + [os.path.expanduser('~/stash')]:\n"
        "        try:\n            print(open(path).read())\n"
        "        except OSError:\n            pass\n"
        "    print('uid', os.getuid())\n"
        "    return _plane_side(p, a, n)\n"
    )
    submission = submission_wrapping(
        tmp_path, {"spheres.py": ("hit_sphere", code), "planes.py": ("plane_side", peek)}
    )
    results, run = grade_as_deployed(autograder, submission, ["2.4", "2.5", "2.6"], tmp_path)
    assert list(scores(results)) == list(shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}))
    assert scores(results) == shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}), results
    visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
    assert "uid" in visible  # what it printed does show (a visible test)
    assert "HIDDEN-INPUTS" not in everything_visible(results)


def test_5_kernel_keyrings_carry_nothing_from_a_hidden_test(release, autograder, tmp_path):
    """A uid's keyring outlives its processes; the sandbox refuses the keyring system calls
    (seccomp), so a hidden test cannot leave its inputs there for a visible one."""
    from raykit_grading.isolation import SECCOMP_ARCHES

    calls = SECCOMP_ARCHES[platform.machine()][1]
    keep = (
        "def hit_sphere(origins, directions, center, radius):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    data = b'HIDDEN-INPUTS ' + repr(center.tolist()).encode()\n"
        f"    libc.syscall({calls['add_key']}, b'user', b'stash', data, len(data), -4)\n"
        f"    libc.syscall({calls['add_key']}, b'user', b'stash', data, len(data), -3)\n"
        "    return _hit_sphere(origins, directions, center, radius)\n"
    )
    fetch = (
        "def plane_side(p, a, n):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    for ring in (-4, -3):\n"
        f"        key = libc.syscall({calls['request_key']}, b'user', b'stash', None, ring)\n"
        "        buffer = ctypes.create_string_buffer(4096)\n"
        f"        got = libc.syscall({calls['keyctl']}, 11, key, buffer, 4096)\n"
        "        print('keyring', ring, key, got, ctypes.get_errno(), buffer.value[:200])\n"
        "    return _plane_side(p, a, n)\n"
    )
    submission = submission_wrapping(
        tmp_path, {"spheres.py": ("hit_sphere", keep), "planes.py": ("plane_side", fetch)}
    )
    results, run = grade_as_deployed(autograder, submission, ["2.4", "2.5", "2.6"], tmp_path)
    assert scores(results) == shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}), results
    visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
    assert "keyring -4 -1 -1 1" in visible  # refused: EPERM
    assert "HIDDEN-INPUTS" not in everything_visible(results)


def test_5_system_v_ipc_carries_nothing_from_a_hidden_test(release, autograder, tmp_path):
    """A System V shared memory segment (like a message queue or a semaphore set) outlives
    its processes, and without an ipc namespace of its own (the chroot kind) every later
    test's uid could open one made mode 666; the sandbox refuses the System V and POSIX
    message queue calls (seccomp), so a hidden test cannot leave its inputs there."""
    shmget, msgget = {"x86_64": (29, 68), "aarch64": (194, 186)}[platform.machine()]
    key = 0x7A170000 + os.getpid() % 0x10000
    keep = (
        "def hit_sphere(origins, directions, center, radius):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    libc.syscall.restype = ctypes.c_long\n    libc.shmat.restype = ctypes.c_void_p\n"
        "    data = b'HIDDEN-INPUTS ' + repr(center.tolist()).encode() + b'\\0'\n"
        f"    shm = libc.syscall({shmget}, {key}, 4096, 0o1666)\n"
        "    if shm >= 0:\n"
        "        address = libc.shmat(int(shm), None, 0)\n"
        "        if address not in (None, 2**64 - 1):\n"
        "            ctypes.memmove(address, data, len(data))\n"
        f"    libc.syscall({msgget}, {key}, 0o1666)\n"
        "    return _hit_sphere(origins, directions, center, radius)\n"
    )
    fetch = (
        "def plane_side(p, a, n):\n"
        "    import ctypes\n    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    libc.syscall.restype = ctypes.c_long\n    libc.shmat.restype = ctypes.c_void_p\n"
        f"    shm = libc.syscall({shmget}, {key}, 0, 0)\n"
        "    print('shm', shm, ctypes.get_errno())\n"
        "    if shm >= 0:\n"
        "        address = libc.shmat(int(shm), None, 0o10000)\n"
        "        if address not in (None, 2**64 - 1):\n"
        "            print(ctypes.string_at(address)[:200])\n"
        f"    print('msg', libc.syscall({msgget}, {key}, 0), ctypes.get_errno())\n"
        "    return _plane_side(p, a, n)\n"
    )
    submission = submission_wrapping(
        tmp_path, {"spheres.py": ("hit_sphere", keep), "planes.py": ("plane_side", fetch)}
    )
    try:
        results, run = grade_as_deployed(autograder, submission, ["2.4", "2.5", "2.6"], tmp_path)
    finally:  # were the defence gone, what it made would outlive the test on this machine
        for kind in ("-M", "-Q"):
            subprocess.run(["ipcrm", kind, hex(key)], capture_output=True)
    assert scores(results) == shown(autograder, {"2.4": 1, "2.5": 2, "2.6": 1}), results
    visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
    assert "shm -1 1" in visible and "msg -1 1" in visible  # refused: EPERM
    assert "HIDDEN-INPUTS" not in everything_visible(results)


def test_9_no_namespace_of_its_own_so_no_memory_beyond_its_limits(release, autograder, tmp_path):
    """clone(CLONE_NEWUSER | CLONE_NEWNS) would make the child root of a user namespace of
    its own (bubblewrap as root leaves that to the kernel), where the new mount API mounts a
    tmpfs that neither the 64 MB /tmp nor the address-space limit bounds. The seccomp filter
    refuses a clone with any CLONE_NEW* flag and the new mount API; the code answers right
    only if it stored nothing."""
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    import os, ctypes, platform\n"
        "    libc = ctypes.CDLL(None, use_errno=True)\n"
        "    libc.syscall.restype = ctypes.c_long\n"
        "    clone = {'x86_64': 56, 'aarch64': 220}[platform.machine()]\n"
        "    libc.prctl(4, 1, 0, 0, 0)  # PR_SET_DUMPABLE: its own /proc files, for uid_map\n"
        "    uid, gid = os.getuid(), os.getgid()\n"
        "    said_r, said_w = os.pipe()\n    go_r, go_w = os.pipe()\n"
        "    pid = libc.syscall(clone, 0x10000000 | 0x00020000 | 17, 0, 0, 0, 0)\n"
        "    if pid == 0:\n"
        "        os.read(go_r, 1)\n        stored = 0\n"
        "        fs = libc.syscall(430, b'tmpfs', 0)  # fsopen\n"
        "        if fs >= 0:\n"
        "            libc.syscall(431, fs, 6, None, None, 0)  # FSCONFIG_CMD_CREATE\n"
        "            mnt = libc.syscall(432, fs, 0, 0)  # fsmount\n"
        "            try:\n"
        "                out = os.open('big', os.O_CREAT | os.O_WRONLY, 0o600, dir_fd=mnt)\n"
        "                for _ in range(200):\n"
        "                    os.write(out, b'x' * 2**20)\n                    stored += 1\n"
        "            except OSError:\n                pass\n"
        "        os.write(said_w, str(stored).encode())\n        os._exit(0)\n"
        "    print('clone', pid, ctypes.get_errno())\n"
        "    stored = 0\n"
        "    if pid > 0:\n"
        "        for name, text in (('setgroups', 'deny'), ('uid_map', f'0 {uid} 1'),\n"
        "                           ('gid_map', f'0 {gid} 1')):\n"
        "            try:\n                open(f'/proc/{pid}/{name}', 'w').write(text)\n"
        "            except OSError:\n                pass\n"
        "        os.write(go_w, b'g')\n        os.waitpid(pid, 0)\n"
        "        stored = int(os.read(said_r, 20) or 0)\n"
        "    print('stored', stored, 'MB')\n"
        "    return _hit_plane(origins, directions, a, n) if not stored else origins[:, 0]\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "clone -1 " in results["tests"][0]["output"]  # refused: EPERM, or ENOSPC as a user
    assert "stored 0 MB" in results["tests"][0]["output"]


def test_9_no_gigabyte_held_by_the_kernel_outside_the_memory_limit(release, autograder, tmp_path):
    """The address-space limit does not count what the kernel holds for a process: memfd
    files (never mapped) and socket buffers. It tries to hold 1 GB in each: memfd_create and
    every socket are refused (seccomp). The code answers right only if it never held 1 GB."""
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    import os, socket\n"
        "    GB, chunk, held, keep = 2**30, b'x' * 2**20, {'memfd': 0, 'sockets': 0}, []\n"
        "    try:\n"
        "        while held['memfd'] < GB:\n"
        "            keep.append(os.memfd_create('hog'))\n"
        "            for _ in range(60):\n"
        "                held['memfd'] += os.write(keep[-1], chunk)\n"
        "    except OSError as e:\n        print('memfd', e.errno)\n"
        "    for fd in keep:\n        os.close(fd)\n"
        "    try:\n"
        "        while held['sockets'] < GB:\n"
        "            pair = socket.socketpair()\n            keep.append(pair)\n"
        "            for end in pair:\n"
        "                end.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 2**23)\n"
        "                end.setblocking(False)\n"
        "                try:\n"
        "                    while held['sockets'] < GB:\n"
        "                        held['sockets'] += end.send(chunk)\n"
        "                except BlockingIOError:\n                    pass\n"
        "    except OSError as e:\n        print('sockets', e.errno)\n"
        "    print('held MB', {k: v >> 20 for k, v in held.items()})\n"
        "    big = max(held.values()) >= GB\n"
        "    return origins[:, 0] if big else _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "memfd 1" in results["tests"][0]["output"]  # refused: EPERM
    assert "sockets 1" in results["tests"][0]["output"]  # refused: EPERM


def test_9_the_sandbox_init_cannot_be_rewritten_to_outlive_the_test(release, autograder, tmp_path):
    """As a normal user, bubblewrap's init (pid 1 in the sandbox) runs as the child's own uid:
    with a /proc the child could write that process's memory through /proc/1/mem (run code
    there that leaves the process group and drops --die-with-parent, and so outlive the
    test). There is no /proc in any sandbox; the code answers right only if it could not
    write another process's memory."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os\n    wrote = 0\n"
        "    try:\n"
        "        maps = open('/proc/1/maps').read().splitlines()\n"
        "        start = int(next(m for m in maps if 'r-xp' in m).split('-')[0], 16)\n"
        "        memory = os.open('/proc/1/mem', os.O_RDWR)\n"
        "        same = os.pread(memory, 4, start)\n"
        "        wrote = os.pwrite(memory, same, start)  # its own bytes: the test harms nothing\n"
        "    except (OSError, StopIteration) as e:\n"
        "        print('refused', type(e).__name__)\n"
        "    print('wrote', wrote)\n"
        "    return origins[:, 0] if wrote else _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "wrote 0" in results["tests"][0]["output"]


def test_9_no_memory_is_there_to_fill_but_a_small_tmp(release, autograder, tmp_path):
    """Writing 100 MB anywhere fails: the tree is read-only but /tmp, which is 64 MB. The code
    answers right only if every big write failed."""
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    stored = []\n"
        "    for path in ('/big', '/dev/shm/big', '/dev/big', '/tmp/big', '/work/big'):\n"
        "        try:\n"
        "            with open(path, 'wb') as out:\n"
        "                for _ in range(100):\n"
        "                    out.write(b'x' * 2**20)\n"
        "            stored.append(path)\n"
        "        except OSError:\n            pass\n"
        "    print('stored', stored)\n"
        "    return _hit_plane(origins, directions, a, n) if not stored else origins[:, 0]\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert "stored []" in results["tests"][0]["output"]


def test_5_a_hidden_tests_error_message_is_not_shown(release, autograder, tmp_path):
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    raise ValueError('INPUTS ' + repr(origins.tolist()))\n"
    )
    submission = submission_with(release, tmp_path, {"planes.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.2", "2.1"], tmp_path)
    assert scores(results) == shown(autograder, {"2.2": 0, "2.1": 0})
    visible, hidden = results["tests"]  # in the catalogue's order (PrairieLearn: hidden last)
    if way(autograder) == "prairielearn":  # one line, nothing of the hidden test's own
        assert hidden["output"].startswith("hidden tests: 0 of 1 points")
    else:
        assert hidden["output"].startswith("your code stopped with an error (a hidden test")
    assert "INPUTS" not in hidden["output"] and "INPUTS" in visible["output"]


# ---- 6: the solution is nowhere the child can read -----------------------------------------

SEARCH = (
    "def hit_plane(origins, directions, a, n):\n"
    "    import os, sys, importlib.util\n"
    "    found = []\n"
    "    for top, dirs, files in os.walk('/', onerror=lambda e: None):\n"
    "        dirs[:] = [d for d in dirs if d not in ('proc', 'sys', 'dev')]\n"
    "        for name in files:\n"
    "            path = os.path.join(top, name)\n"
    "            try:\n"
    "                text = open(path, errors='replace').read(200000)\n"
    "            except OSError:\n                continue\n"
    "            if 'CANARY-7f3a' in text or 'secret.txt' in name:\n"
    "                print('FOUND', path, text[:40])\n"
    "            if name == 'planes.py' and '(a - origins) @ n' in text:\n"
    "                found.append(path)\n"
    "    for path in found:\n"
    "        spec = importlib.util.spec_from_file_location('reference_planes', path)\n"
    "        module = importlib.util.module_from_spec(spec)\n"
    "        spec.loader.exec_module(module)\n"
    "        return module.hit_plane(origins, directions, a, n)\n"
    "    import numpy\n"
    "    return numpy.zeros(len(origins))\n"
)


def test_6_a_submission_that_searches_the_disk_finds_no_solution(
    release, autograder, canary, tmp_path
):
    submission = tmp_path / "submission"
    shutil.copytree(release / "raykit", submission / "raykit")
    with open(submission / "raykit/planes.py", "a") as module:
        module.write("\n" + SEARCH)
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 0}, results
    assert "CANARY" not in everything_visible(results) and "FOUND" not in everything_visible(
        results
    )


def test_6_nothing_outside_the_sandbox_is_written(release, autograder, canary, tmp_path):
    """It answers right, and on the way tries to leave files everywhere it might: they all
    stay inside its own sandbox (gone after the test), and it keeps its full score."""
    marker = f"written-by-a-submission-{os.getpid()}"
    targets = [
        f"/tmp/{marker}",
        str(canary.parent / marker),
        str(REPO / marker),
        str(autograder / "source" / marker),
        str(tmp_path / marker),
        f"/var/tmp/{marker}",
        f"/dev/shm/{marker}",
    ]
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os\n"
        f"    for path in {targets!r}:\n"
        "        try:\n            open(path, 'w').write('x')\n"
        "        except OSError:\n            pass\n"
        "    return _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results
    assert [path for path in targets if os.path.exists(path)] == []


# ---- 7: the results are the grader's; killing it loses nothing ----------------------------


def test_7_forged_results_and_a_killed_parent_change_nothing(release, autograder, tmp_path):
    targets = [
        str(autograder / "results/results.json"),
        str(tmp_path / "results/results.json"),
        "/autograder/results/results.json",  # where the container way's grader writes it
    ]
    code = (
        "import json, os, signal\n"
        f"for path in {targets!r}:\n"
        "    try:\n"
        "        open(path, 'w').write(json.dumps({{'score': 1000, 'tests': []}}))\n"
        "    except OSError:\n        pass\n"
        "for pid in (os.getppid(), 1, -1):\n"
        "    try:\n        os.kill(pid, signal.SIGKILL)\n"
        "    except OSError:\n        pass\n"
    )
    submission = tmp_path / "submission"
    shutil.copytree(release / "raykit", submission / "raykit")
    with open(submission / "raykit/__init__.py", "a") as module:
        module.write("\n" + code.replace("{{", "{").replace("}}", "}"))
    results, run = grade_as_deployed(autograder, submission, ["2.1", "3.6"], tmp_path)
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": 0, "3.6": 0}
    assert results["score"] == 0 and len(results["tests"]) == 2


# ---- 8: a grader that cannot grade says so, before grading anyone --------------------------


def test_8_no_usable_child_python_is_one_line_and_a_non_zero_exit(tmp_path):
    submission = make_submission(tmp_path / "submission")
    out = tmp_path / "r.json"
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o", str(out),
         "--only", "2.1", "--child-python", "/nonexistent/python3"],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert run.returncode == 3
    assert "Traceback" not in run.stderr
    assert run.stderr.startswith("raykit_grading: error: cannot grade: cannot run the child")
    results = json.loads(out.read_text())
    assert results["tests"][0]["output"].startswith("NOT GRADED")
    batch = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "batch", str(tmp_path), "-o",
         str(tmp_path / "out"), "--child-python", "/nonexistent/python3"],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert batch.returncode == 3 and "Traceback" not in batch.stderr
    assert not (tmp_path / "out/scores.csv").exists()


# ---- 9: classmates, the network, and outliving the test -------------------------------------


class _Listener:
    """A TCP server on loopback that counts the connections it gets."""

    def __init__(self) -> None:
        self.server = socket.socket()
        self.server.bind(("127.0.0.1", 0))
        self.server.listen()
        self.server.settimeout(0.2)
        self.port = self.server.getsockname()[1]
        self.connections = 0
        self.running = True
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        while self.running:
            try:
                connection, _ = self.server.accept()
            except OSError:
                continue
            self.connections += 1
            connection.close()

    def close(self) -> None:
        self.running = False
        self.thread.join()
        self.server.close()


def test_9_classmates_network_and_daemons_in_a_batch(release, tmp_path):
    """In one batch: mallory looks for her classmate's folder (through the grader's command
    line in /proc and by walking the disk), sends her inputs to a server on this machine, and
    leaves a daemon behind; ada's work and the class's scores.csv come out untouched."""
    listener = _Listener()
    students = tmp_path / "submissions"
    make_submission(students / "ada")
    (students / "ada/raykit/ada_marker.py").write_text("# ADA-SECRET-WORK\n")
    marker = f"DAEMON-{os.getpid()}"
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    import os, socket, subprocess, sys, glob\n"
        "    seen = []\n"
        "    for cmd in glob.glob('/proc/*/cmdline'):\n"
        "        try:\n            seen.append(open(cmd).read())\n"
        "        except OSError:\n            pass\n"
        "    for top, dirs, files in os.walk('/', onerror=lambda e: None):\n"
        "        dirs[:] = [d for d in dirs if d not in ('proc', 'sys', 'dev')]\n"
        "        for name in files:\n"
        "            if name == 'ada_marker.py':\n"
        "                print(open(os.path.join(top, name)).read())\n"
        "    print('PROCS', [s for s in seen if 'ada' in s])\n"
        "    try:\n"
        f"        socket.create_connection(('127.0.0.1', {listener.port}), timeout=1)"
        ".sendall(origins.tobytes())\n"
        "    except OSError as e:\n        print('NET', e)\n"
        "    if os.fork() == 0:\n"
        "        os.setsid()\n"
        f"        os.execv(sys.executable, [sys.executable, '-c', 'import time; time.sleep(60)',"
        f" '{marker}'])\n"
        "    import numpy\n    return numpy.zeros(len(origins))\n"
    )
    mallory = make_submission(students / "mallory")
    with open(mallory / "raykit/planes.py", "a") as module:
        module.write("\n" + code)
    out = tmp_path / "out"
    try:
        run = subprocess.run(
            [sys.executable, "-m", "raykit_grading", "batch", str(students), "-o", str(out),
             "--only", "2.1", "2.3", "--wall-seconds", str(WALL), "--jobs", "2"],
            capture_output=True, text=True, cwd=tmp_path, timeout=300,
        )  # fmt: skip
    finally:
        listener.close()
    assert run.returncode == 0, run.stderr[-2000:]
    rows = {row["student"]: row for row in csv.DictReader((out / "scores.csv").open())}
    assert {k: (rows[k]["status"], float(rows[k]["score"])) for k in rows} == {
        "ada": ("graded", 4.0),
        "mallory": ("graded", 2.0),
    }
    feedback = (out / "feedback/mallory/results.json").read_text()
    assert "ADA-SECRET-WORK" not in feedback and "PROCS []" in feedback
    assert "NET" in feedback and listener.connections == 0
    assert processes_naming(marker) == []


def test_batch_goes_on_past_a_student_it_cannot_grade_and_resumes(release, tmp_path):
    students = tmp_path / "submissions"
    make_submission(students / "ada")
    make_submission(students / os.fsdecode(b"b\xf8rge"))  # a name that is not UTF-8
    (students / "empty").mkdir()  # no raykit/ at all
    out = tmp_path / "out"
    command = [sys.executable, "-m", "raykit_grading", "batch", str(students), "-o", str(out),
               "--only", "2.1"]  # fmt: skip
    first = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert first.returncode == 1
    assert "empty: could not grade: no raykit package" in first.stderr
    rows = _rows(out / "scores.csv")
    assert rows["ada"]["status"] == "graded" and float(rows["ada"]["score"]) == 2
    assert rows[os.fsdecode(b"b\xf8rge")]["status"] == "graded"
    make_submission(students / "bob")
    again = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert "4 submissions: 3 graded, 1 not graded" in again.stdout and again.returncode == 1
    rows = _rows(out / "scores.csv")
    assert rows["bob"]["status"] == "graded"


def _rows(path: Path) -> dict[str, dict]:
    with open(path, newline="", encoding="utf-8", errors="surrogateescape") as stream:
        return {row["student"]: row for row in csv.DictReader(stream)}


def test_a_slow_submission_is_stopped_by_the_total_budget(release, autograder, tmp_path):
    """It sleeps at import: every test times out until the total is used up, then the rest
    are not run: at most the two tests that 6 s of 4 s tests can start are run."""
    submission = submission_with(release, tmp_path, {"__init__.py": "import time\ntime.sleep(60)"})
    only = ["2.1", "2.3", "3.1", "4.1", "4.6"]
    results, run = grade_as_deployed(
        autograder, submission, only, tmp_path, extra="--total-seconds 6"
    )
    assert all(score == 0 for score in scores(results).values())
    not_run = ["not run: all tests together" in t["output"] for t in results["tests"]]
    assert sum(not_run) >= len(only) - 2, results


def test_a_right_submission_that_writes_to_devnull_keeps_its_score(autograder, tmp_path):
    """Quieting output into os.devnull works in every sandbox: the chroot tree's /dev/null is
    mode 666 (mknod took the umask) and Landlock lets the child write it, so Gradescope's
    sandbox scores this as bubblewrap does."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os\n"
        "    with open(os.devnull, 'w') as quiet:\n        quiet.write('progress')\n"
        "    return _hit_plane(origins, directions, a, n)\n"
    )
    submission = submission_wrapping(tmp_path, {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert scores(results) == {"2.1": 2}, results


def test_a_correct_submission_scores_full_marks_as_deployed(autograder, tmp_path):
    results, run = grade_as_deployed(
        autograder, make_submission(tmp_path / "submission"), [t.key for t in TESTS], tmp_path
    )
    assert run.returncode == 0, run.stderr[-2000:]
    failed = [(t["number"], t["output"][:300]) for t in results["tests"] if t["status"] != "passed"]
    assert failed == []
    assert results["score"] == pytest.approx(sum(POINTS.values()))


# ---- 10: what one test leaves reaches no other test, and no later student -----------------

# the attacks of this section, each written into the solution's hit_plane (test 2.1), which
# then answers right: a test that keeps to its disk budget keeps its score
DEEP_TREE = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    here = os.open(os.environ['HOME'], os.O_RDONLY)\n"
    "    for _ in range(200_000):\n"
    "        os.mkdir('d', dir_fd=here)\n"
    "        deeper = os.open('d', os.O_RDONLY, dir_fd=here)\n"
    "        os.close(here)\n        here = deeper\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
RESERVED = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    fd = os.open(os.path.join(os.environ['HOME'], 'big'), os.O_CREAT | os.O_WRONLY)\n"
    "    try:\n        os.posix_fallocate(fd, 0, 960 * 2**20)\n"
    "    except OSError as e:\n        print('FALLOCATE', e.errno)\n"
    "    os.ftruncate(fd, 60 * 2**20)  # sparse: no block held\n"
    "    print('HELD', os.fstat(fd).st_blocks * 512)\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
WRITES_TOO_MUCH = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    block = b'x' * 2**20\n"
    "    for i in range(200):\n"
    "        with open(os.path.join(os.environ['HOME'], f'f{i}'), 'wb') as f:\n"
    "            for _ in range(50):\n                f.write(block)\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
CLOSED_LEFTOVERS = (
    "def hit_plane(origins, directions, a, n):\n    import os\n"
    "    home = os.environ['HOME']\n"
    "    os.makedirs(os.path.join(home, 'a/b/c'))\n"
    "    os.mkfifo(os.path.join(home, 'a/b/c/pipe'))\n"
    "    open(os.path.join(home, 'a/b/file'), 'w').write('x')\n"
    "    for folder in ('a/b/c', 'a/b', 'a'):\n"
    "        os.chmod(os.path.join(home, folder), 0)\n"
    "    return _hit_plane(origins, directions, a, n)\n"
)
DISK_ATTACKS = {
    "a tree too deep to name": (DEEP_TREE, 0, "used more disk than allowed"),
    "200 files of 50 MB": (WRITES_TOO_MUCH, 0, "used more disk than allowed"),
    "960 MB reserved, 60 MB sparse": (RESERVED, 2, "FALLOCATE 1\nHELD 0"),
    "folders closed to their owner, a FIFO": (CLOSED_LEFTOVERS, 2, "the grader removed them"),
}


def _leftovers() -> list[str]:
    """What no running grader holds: test folders' contents in the chroot trees' slots,
    graders' workspaces, the quarantines."""
    found = []
    for slot in TREES.glob("tree-*/tasks/*") if AS_ROOT else ():
        lock = TREES / f".slots-{slot.parent.parent.name}" / slot.name
        if not _held(lock):
            found += [str(p) for p in slot.iterdir()]
    for quarantine in [
        TREES / "quarantine",
        Path(tempfile.gettempdir()) / "raykit-grading-quarantine",
    ]:
        if quarantine.is_dir():
            found += [str(p) for p in quarantine.iterdir()]
    for folder in Path(tempfile.gettempdir()).glob("raykit-grading-*"):
        if folder.name != "raykit-grading-quarantine" and not _held(folder / ".lock"):
            found.append(str(folder))
    return found


@pytest.mark.parametrize("name", sorted(DISK_ATTACKS))
def test_10_disk_attacks_cost_their_own_test_and_leave_nothing(name, autograder, tmp_path):
    """Each attack in 2.1, beside an honest 2.3: the attack's test scores what its budget
    allows (a test past its budget is stopped and scores 0, saying so; one within it keeps
    its score, told what the grader had to force), 2.3 is graded in full, nothing is left on
    disk, and the solution graded right after on the same machine scores in full."""
    code, points, says = DISK_ATTACKS[name]
    submission = submission_wrapping(tmp_path / "attack", {"planes.py": ("hit_plane", code)})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "2.3"], tmp_path / "a")
    assert run.returncode == 0, run.stderr[-2000:]
    assert scores(results) == {"2.1": points, "2.3": 2}, results
    assert says in results["tests"][0]["output"], results["tests"][0]["output"]
    assert "autograder failed" not in everything_visible(results)
    assert _leftovers() == []
    honest = make_submission(tmp_path / "honest" / "submission")
    results, run = grade_as_deployed(autograder, honest, ["2.1", "2.3"], tmp_path / "h")
    assert run.returncode == 0 and scores(results) == {"2.1": 2, "2.3": 2}, results


SPY = (
    "def plane_side(p, a, n):\n    import os, json\n"
    "    home = os.environ['HOME']\n    seen = {{}}\n"
    "    looks = [('parent', '..'), ('here', '.'), ('tmp', home), ('tmp parent', home + '/..')]\n"
    "    for what, path in looks:\n"
    "        try:\n"
    "            got = os.stat(path)\n"
    "            seen[what] = [got.st_nlink, got.st_size]\n"
    "        except OSError as e:\n            seen[what] = e.strerror\n"
    "    seen['tmp entries'] = sorted(os.listdir(home))\n"
    "    try:\n        seen['free inodes'] = os.statvfs(home).f_ffree\n"
    "    except OSError as e:\n        seen['free inodes'] = e.strerror\n"
    "    print('SPY', json.dumps(seen, sort_keys=True))\n"
    "    return _plane_side(p, a, n)\n"
)
LEAVE = (
    "def hit_sphere(origins, directions, center, radius):\n    import os\n"
    "    home = os.environ['HOME']\n"
    "    count = int(abs(center[0]) * 100) % 500 + 1  # the hidden input, as a count\n"
    "    for i in range(count):\n        os.mkdir(os.path.join(home, f'x{{i}}'))\n"
    "    return _hit_sphere(origins, directions, center, radius)\n"
)


def test_10_visible_tests_run_before_hidden_ones():
    from raykit_grading.catalog import VISIBLE
    from raykit_grading.grade import _visible_first

    order = [t.visibility == VISIBLE for t in _visible_first(TESTS)]
    assert order == sorted(order, reverse=True) and order.count(True) == sum(
        t.visibility == VISIBLE for t in TESTS
    )


def test_10_a_test_sees_nothing_of_the_tests_before_it(release, autograder, tmp_path):
    """Hidden 2.4 and 2.5 leave folders in their tmp/ counted from their inputs; visible
    2.6 (graded with them) and 2.1's plane side look at everything they can stat: their
    folder's parent, their tmp/ and its parent, the free inodes. What each visible test sees is
    the same, whatever ran before it: the folder's parent and tmp/ are the same fixed ones,
    tmp/ is empty, and the file system's counts are refused. (Their times are not compared: a
    folder is as old as the grading or its container, which says nothing of an earlier test,
    and comparing their age with a few seconds failed on a loaded machine.)"""
    submission = submission_wrapping(
        tmp_path,
        {"spheres.py": ("hit_sphere", LEAVE.format()), "planes.py": ("plane_side", SPY.format())},
    )
    seen = []
    for only in (["2.6"], ["2.4", "2.5", "2.6"], ["2.3", "2.4", "2.6"]):
        results, run = grade_as_deployed(autograder, submission, only, tmp_path / "-".join(only))
        assert run.returncode == 0, run.stderr[-2000:]
        visible = next(t for t in results["tests"] if t["number"] == "2.6")["output"]
        seen.append(re.search(r"SPY (.*)", visible).group(1))
    assert seen[0] == seen[1] == seen[2], seen
    facts = json.loads(seen[0])
    assert facts["tmp entries"] == [] and facts["free inodes"] == "Operation not permitted"


# ---- 11: every budget holds, and nothing shown at once tells of a hidden test ----------------

# tests/support/budget_attacks.py, all in one submission: each attack in a function of its own
BUDGETED = ["2.1", "2.3", "2.4", "2.5", "2.6", "2.7", "4.1", "4.2"]
BUDGETED_SCORES = {"2.1": 0, "2.3": 2, "2.4": 0, "2.5": 0, "2.6": 1, "2.7": 1, "4.1": 0, "4.2": 0}
# the page tables' 480 MB are within a test's memory where no container (root, user) or a
# 2 GB one (PrairieLearn's) leaves it more, past it at Gradescope's 768 MB (docker, container)
PAGE_TABLES_WITHIN = ("root", "user", "prairielearn")
BUDGETED_SAY = {  # what each visible test's output says
    "2.1": ["your code used more disk than allowed", "with no name"],
    "2.6": ["socketpair 1", "fork 1", "F_SETPIPE_SZ 1", "held 0 MB"],
    "2.7": ["fork 1", "children held 0 MB"],
    "4.1": ["your code used more memory than allowed", "page tables"],
    "4.2": ["returned something that is not plain arrays", "more than 16 arrays"],
}
PEAK = re.compile(r"raykit_grading: the grader's peak memory: (\d+) MB of the (\d+) MB it keeps")
OOM = re.compile(r"the container's OOM killer fired (\d+) times")


def test_11_every_budget_holds_and_hidden_outcomes_stay_hidden(autograder, tmp_path):
    """Files with no name, kernel buffers in sockets and pipes, memory across processes, page
    tables, an archive of 100,000 empty members, and hidden tests that fail: every test past a
    budget is stopped and told which, what must be refused is, and the summary shown at once
    is the honest submission's. The grader stays within its own memory, the container's OOM
    killer never fires, nothing is left, and the honest submission graded next scores in full.
    (That execution_time counts the visible tests only is test_grading's, on a clock of its
    own.)"""
    attacker = budget_attacker(tmp_path / "attack" / "submission")
    results, run = grade_as_deployed(autograder, attacker, BUDGETED, tmp_path / "a")
    print(way(autograder), scores(results), results["output"])
    print({t["number"]: t["output"][-600:] for t in results["tests"]}, run.stderr[-1500:])
    assert run.returncode == 0, run.stderr[-2000:]
    within = way(autograder) in PAGE_TABLES_WITHIN
    assert scores(results) == shown(autograder, {**BUDGETED_SCORES, "4.1": int(within)}), results
    said = {t["number"]: t["output"] for t in results["tests"]}
    for key, words in BUDGETED_SAY.items():
        words = ["MAPPINGS 20000"] if key == "4.1" and within else words
        assert all(w in said[key] for w in words), (key, said[key])
    assert _leftovers() == []
    honest = make_submission(tmp_path / "honest" / "submission")
    fair, fair_run = grade_as_deployed(autograder, honest, BUDGETED, tmp_path / "h")
    assert fair_run.returncode == 0, fair_run.stderr[-2000:]
    assert scores(fair) == shown(autograder, {k: POINTS[k] for k in BUDGETED}), fair
    summary = [  # shown at once: the visible tests' sums, and of the hidden ones no outcome
        "Stage 2 rays, planes and spheres: 4 of 6 points, 3 of 4 visible tests pass",
        f"Stage 4 shading, shadows and mirrors: {int(within)} of 2 points, {int(within)} of 2 "
        "visible tests pass",
        "Hidden tests: 2, 3 points (how they went is not shown here)",
    ]
    assert results["output"].splitlines()[1:] == summary, results["output"]
    assert fair["output"].splitlines()[-1] == summary[-1]
    for graded in (run, fair_run):
        peak = PEAK.search(graded.stderr)
        assert peak and int(peak.group(1)) <= int(peak.group(2)), graded.stderr[-1500:]
        if way(autograder) in ("docker", "container", "prairielearn"):
            assert OOM.search(graded.stderr).group(1) == "0", graded.stderr[-1500:]


# batch runs on an instructor's machine, as root or as a normal user (bubblewrap's sandbox);
# in a container only run_autograder and PrairieLearn's entrypoint grade, one submission each
BATCH_WAYS = ("root", "user")


@pytest.mark.parametrize("graded_as", BATCH_WAYS)
def test_11_a_batch_grades_honest_students_between_attackers_in_full(graded_as, tmp_path):
    """One batch on one machine grades ada, then mallory (issue 40's disk: a tree too deep to
    name, 200 files of 50 MB), then trudy (every attack of tests/support/budget_attacks.py),
    then zoe: ada and zoe score in full, test for test; mallory and trudy exactly what
    test_10's and test_11's attacks score, each of their pages (linked from the class report)
    naming the budget that stopped them; every student's grader stays within its own memory
    (its log, ``logs/<student>.log``), the OOM killer never fires where its cgroup says, and
    nothing is left."""
    students = tmp_path / "submissions"
    make_submission(students / "ada")
    mallory = submission_wrapping(
        tmp_path / "m",
        {
            "planes.py": ("hit_plane", DEEP_TREE),
            "spheres.py": (
                "hit_sphere",
                WRITES_TOO_MUCH.replace("hit_plane", "hit_sphere").replace(
                    "origins, directions, a, n", "origins, directions, center, radius"
                ),
            ),
        },
    )
    shutil.copytree(mallory, students / "mallory")
    budget_attacker(students / "trudy")
    make_submission(students / "zoe")
    out, run = _batch_as(graded_as, students, tmp_path / "graded")
    assert run.returncode == 0, run.stderr[-2000:]
    rows = {row["student"]: row for row in csv.DictReader((out / "scores.csv").open())}
    full = {k: POINTS[k] for k in BUDGETED}
    within = int(graded_as in PAGE_TABLES_WITHIN)
    assert {k: (r["status"], {t: float(r[t]) for t in BUDGETED}) for k, r in rows.items()} == {
        "ada": ("graded", full),
        "mallory": ("graded", {**full, "2.1": 0, "2.3": 0, "2.4": 0, "2.5": 0}),
        "trudy": ("graded", {**BUDGETED_SCORES, "4.1": within}),
        "zoe": ("graded", full),
    }, run.stderr[-2000:]
    report = (out / "report.html").read_text()
    pages = {name: html.unescape((out / "feedback" / name / "index.html").read_text())
             for name in rows if f"href='feedback/{name}/index.html'" in report}  # fmt: skip
    assert sorted(pages) == sorted(rows), report
    stopped = {("mallory", "2.1"): "used more disk than allowed",
               ("mallory", "2.3"): "used more disk than allowed",
               ("trudy", "2.1"): BUDGETED_SAY["2.1"][0], ("trudy", "4.2"): BUDGETED_SAY["4.2"][0],
               **({} if within else {("trudy", "4.1"): BUDGETED_SAY["4.1"][0]})}  # fmt: skip
    for (name, key), budget in stopped.items():  # on the page the report links
        told = re.sub(r"<[^>]+>", " ", _failing_on(pages[name], key))
        assert budget in told, f"{name}'s {key} was not stopped for {budget!r}: {told!r}"
    trudy = json.loads((out / "feedback/trudy/results.json").read_text())
    said = {t["number"]: t["output"] for t in trudy["tests"]}
    for key, words in {**BUDGETED_SAY, **({"4.1": ["MAPPINGS 20000"]} if within else {})}.items():
        assert all(w in said[key] for w in words), (
            f"trudy's {key} does not say {words}: {said[key]!r}"
        )
    for name in rows:
        log = (out / "logs" / f"{name}.log").read_text()
        peak = PEAK.search(log)
        assert peak and int(peak.group(1)) <= int(peak.group(2)), (name, log[-1500:])
        killed = OOM.search(log)  # a container's cgroup says; an instructor's machine may not
        assert killed is None or killed.group(1) == "0", (name, log[-1500:])
    assert _leftovers() == []


def _failing_on(page: str, key: str) -> str:
    """What a student's feedback page says of test ``key`` where it lists it as failing ("" if
    it does not)."""
    name = next(t.name for t in TESTS if t.key == key)
    found = re.search(f"FAIL: {re.escape(name)}:(.*?)</section>", page, re.S)
    return found.group(1) if found else ""


def _batch_as(
    graded_as: str, students: Path, out: Path
) -> tuple[Path, subprocess.CompletedProcess]:
    """``python -m raykit_grading batch`` of ``students`` with the budgeted tests, one student
    at a time, each test with its own wall time: as root (``root``), or as a normal user
    (``user``: as root, uid 65534 through ``setpriv`` with a Python of raykit's dependencies,
    in a folder of its own, its TMPDIR, which must hold nothing of the graders afterwards);
    returns OUT and the run."""

    def batch(python: str, students: Path, out: Path) -> list[str]:
        # a test's own wall time, as an instructor's batch has it: every attack here is
        # stopped by its budget or let be long before it while its defences hold (and one
        # that is not shows as its time running out), and the page tables' 20,000 mappings
        # (4.1, within its budget here) must not be stopped by the time a loaded machine takes
        return [python, "-m", "raykit_grading", "batch", str(students), "-o", str(out),
                "--only", *BUDGETED, "--jobs", "1", "--seed", str(SEED)]  # fmt: skip

    if graded_as == "root" and not AS_ROOT:
        pytest.skip("the root way runs batch as root")
    if graded_as == "root" or not AS_ROOT:  # as the suite's user
        run = subprocess.run(batch(sys.executable, students, out), capture_output=True,
                             text=True, cwd=out.parent, timeout=900)  # fmt: skip
        return out, run
    from grader_python import instructor_python

    python, why = instructor_python()
    if python is None or shutil.which("setpriv") is None:
        pytest.skip(why or "as root, the user way needs setpriv to become uid 65534")
    home = Path(tempfile.mkdtemp(prefix="raykit-user-", dir="/tmp"))
    try:
        shutil.copytree(students, home / "submissions")
        (home / "home").mkdir()  # matplotlib's cache and configuration
        subprocess.run(["chown", "-R", f"{NOBODY}:{NOBODY}", str(home)], check=True)
        run = subprocess.run(
            ["setpriv", f"--reuid={NOBODY}", f"--regid={NOBODY}", "--clear-groups",
             *batch(python, home / "submissions", home / "out")],
            capture_output=True, text=True, timeout=900, cwd=home,
            env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(REPO), "TMPDIR": str(home),
                 "HOME": str(home / "home")},
        )  # fmt: skip
        left = sorted(
            p.name for p in home.iterdir() if p.name not in ("submissions", "out", "home")
        )
        assert left == [], f"the graders left {left} in their TMPDIR"
        shutil.copytree(home / "out", out)
    finally:
        shutil.rmtree(home, ignore_errors=True)
    return out, run


def test_removal_copes_with_any_tree_a_child_can_leave(tmp_path):
    """Folders nested deeper than a path can name, closed to their owner, FIFOs, sockets and
    links: removed by a walk that never recurses; as a normal user too, where the owner must
    open what it closed."""
    from raykit_grading.leftovers import remove_tree

    def plant(top: Path) -> None:
        here = os.open(top, os.O_RDONLY)
        for _ in range(1500):  # 1500 x len("nested/") passes PATH_MAX
            os.mkdir("nested", dir_fd=here)
            deeper = os.open("nested", os.O_RDONLY, dir_fd=here)
            os.close(here)
            here = deeper
        os.mkfifo("pipe", dir_fd=here)
        os.symlink("/etc/passwd", "link", dir_fd=here)
        os.close(here)
        (top / "closed" / "inner").mkdir(parents=True)
        (top / "closed" / "inner" / "file").write_text("x")
        bound = socket.socket(socket.AF_UNIX)
        bound.bind(str(top / "closed" / "socket"))
        bound.close()
        os.chmod(top / "closed" / "inner", 0)
        os.chmod(top / "closed", 0o500)

    tree = tmp_path / "left"
    tree.mkdir()
    plant(tree)
    with pytest.raises((RecursionError, OSError)):
        shutil.rmtree(tree)  # what the grader used to call: raises part way, or never ends
    removal = remove_tree(tree, tmp_path / "quarantine")
    assert removal.problem == "" and not tree.exists() and removal.left_in is None
    assert removal.forced == {
        "special files (FIFOs, sockets or devices)",
        "folders closed to their owner",
    }
    assert os.listdir(tmp_path) == []


def test_removal_sets_aside_what_it_cannot_finish_in_time(tmp_path):
    from raykit_grading.leftovers import remove_tree

    tree = tmp_path / "left"
    (tree / "a" / "b").mkdir(parents=True)
    removal = remove_tree(tree, tmp_path / "quarantine", seconds=-1)
    assert not tree.exists() and removal.left_in.parent == tmp_path / "quarantine"
    assert "took too long" in removal.problem and (removal.left_in / "a").is_dir()


def _held(lock: Path) -> bool:
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


def test_nothing_is_left_behind(autograder):
    """No process of a sandbox uid, no grader workspace, nothing in a chroot tree's test
    folder and nothing in a quarantine that no running grader holds (this runs after the
    tests above, for each way)."""
    from raykit_grading.isolation import SANDBOX_UIDS, UID_LOCKS

    if way(autograder) in ("container", "prairielearn"):  # every grading's container
        for name in CONTAINERS:  # removed (by its name: others may grade on the same daemon)
            inspected = subprocess.run(
                ["docker", "container", "inspect", name], capture_output=True
            )
            assert inspected.returncode != 0, f"container {name} left"
    assert _leftovers() == []
    uids = set(SANDBOX_UIDS)
    left = []
    for proc in Path("/proc").iterdir():
        try:
            uid = proc.stat().st_uid
        except FileNotFoundError:  # a process of this machine that ended meanwhile
            continue
        if proc.name.isdigit() and uid in uids and not _held(UID_LOCKS / str(uid)):
            left.append(proc.name)
    assert left == []


def test_read_returned_refuses_what_is_not_plain_stored_arrays():
    import io

    from raykit_grading.sandbox import read_returned

    good = io.BytesIO()
    np.savez(good, t=np.arange(4.0))
    assert read_returned(good.getvalue(), 2**20)["t"].tolist() == [0, 1, 2, 3]
    squeezed = io.BytesIO()
    np.savez_compressed(squeezed, t=np.zeros(10))
    for bad in (squeezed.getvalue(), b"PK" + b"\0" * 100, good.getvalue()[:-30]):
        with pytest.raises(ValueError):
            read_returned(bad, 2**20)
    with pytest.raises(ValueError):
        read_returned(good.getvalue(), 10)


def test_the_ways_kept_name_tests_that_exist():
    """A test renamed is not silently dropped from the emulation's or PrairieLearn's way."""
    tests = {name for name in globals() if name.startswith("test_")}
    assert PRAIRIELEARN_DIFFERS | EMULATION_DIFFERS <= tests

"""The hostile suite's fixtures: the autograder of each way, made once a session (a
worker runs one way: see the root conftest.py), and each defence paid for once."""

from __future__ import annotations

import os
import shutil
import zipfile
from pathlib import Path

import pytest

from hostile.deployed import (
    DEPLOYMENTS,
    EMULATION_DIFFERS,
    PRAIRIELEARN_DIFFERS,
    SEED,
    container_image,
    container_way_runs,
    deployment_skip,
    prairielearn_image,
)
from raykit_grading.platforms.gradescope import build_zip


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


@pytest.fixture(scope="session", params=DEPLOYMENTS)
def autograder(request, tmp_path_factory, grader_python):
    """The autograder zip unpacked as Gradescope does (into ``source/``, ``run_autograder``
    copied from there beside it), source closed to everyone but root; its folder's name ends in
    the way it is graded (:data:`DEPLOYMENTS`)."""
    why = deployment_skip(request.param)
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
            from raykit_grading.platforms.prairielearn import write_course_files

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


@pytest.hookimpl(trylast=True)  # after pytest has grouped the tests by their way
def pytest_collection_modifyitems(items):
    """test_nothing_is_left_behind runs after every other test of its way."""
    last = [i for i in items if getattr(i, "originalname", "") == "test_nothing_is_left_behind"]
    rest = [i for i in items if i not in last]
    for item in last:
        deployed = item.callspec.params["autograder"]
        same = [n for n, i in enumerate(rest) if _deployed(i) == deployed]
        rest.insert(same[-1] + 1 if same else len(rest), item)
    items[:] = rest


def _deployed(item) -> str | None:
    callspec = getattr(item, "callspec", None)
    return callspec.params.get("autograder") if callspec else None

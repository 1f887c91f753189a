"""The test suite's two speeds (README, "Quick start"; CONTRIBUTING.md).

``python -m pytest -m "not slow"`` is the quick suite a student runs while working: every test of
the math, the renderer, the formats and the command line. ``python -m pytest`` is the full suite
CI runs: it adds what takes seconds a test, marked ``slow`` here in one place:

* the lecture notebooks, each run by nbval;
* the grader's tests, each grading submissions in sandboxes;
* the compiled engine's, which compile or load numba kernels;
* commands run whole: the benchmarks, the committed pictures remade, outputs under other machines'
  settings;
* the documentation site, built and measured page by page in headless Chromium (test_site.py,
  skipped without the docs extra or Chromium), and the lecture's slide deck, made and shown
  slide by slide at 1920 x 1080 (test_deck.py, the same).
"""

from __future__ import annotations

import pytest

SLOW_MODULES = {
    "test_grade.py",
    "test_batch.py",
    "test_report.py",
    "test_isolation.py",
    "test_base.py",
    "test_chroot.py",
    "test_confine.py",
    "test_kinds.py",
    "test_workspace.py",
    "test_seeds.py",
    "test_submissions.py",
    "test_markers.py",
    "test_release.py",
    "test_main.py",
    "test_benchmarks.py",
    "test_reproducible.py",
    "test_baselines.py",
    "test_gallery.py",
    "test_machine_independent.py",
    "test_site.py",
    "test_deck.py",
}
SLOW_FOLDERS = {"compiled", "hostile"}  # tests/compiled/: the compiled engine's; the hostile suite


# The suite runs on every core (pytest-xdist: ``-n auto`` in pyproject.toml), a test on
# whichever worker is free, except these groups, each kept on one worker in its order: a
# notebook's cells (each runs on the kernel the cells before it left); the tests of a module
# whose costly fixture is made once a module; the modules of the class tests/conftest.py grades
# once a session (graded_class); and the hostile suite one way of grading at a time (its
# autograder is made once a way), with the module that builds the same image for that way.
# xdist's own groups (the xdist_group mark) are lost on pytest 9.2 (pytest-xdist issue 1386), so
# the scheduler below reads the groups from the tests' ids.
ONE_WORKER_MODULES = {
    "test_deck.py",
    "test_seeds.py",
    "test_linescan3d.py",
    "test_site.py",
}
SAME_CLASS = {"test_batch.py", "test_report.py"}  # the grading/ modules using graded_class
SAME_IMAGE = {
    "test_containers.py": "container",
    "test_prairielearn.py": "prairielearn",
}
HOSTILE = "hostile"  # tests/grading/hostile/: its tests' ids hold the way they grade: [root-...]
WAYS = ("root", "docker", "user", "container", "prairielearn")


def worker_group(nodeid: str) -> str | None:
    """The group a test's id puts it in (its worker shared with the group's other tests), or
    None: a test that any worker may run."""
    path, _, test = nodeid.partition("::")
    folder, _, name = path.rpartition("/")
    if name.endswith(".ipynb") or name in ONE_WORKER_MODULES:
        return path
    if name in SAME_CLASS:
        return "grading-class"
    if name in SAME_IMAGE:
        return f"grading-{SAME_IMAGE[name]}"
    if folder.rsplit("/", 1)[-1] == HOSTILE and test.endswith("]"):
        params = test[test.index("[") + 1 : -1].split("-")
        way = next((way for way in (params[0], params[-1]) if way in WAYS), None)
        return f"grading-{way}" if way else None
    return None


@pytest.hookimpl(optionalhook=True, tryfirst=True)  # before xdist's own choice
def pytest_xdist_make_scheduler(config, log):
    from xdist.scheduler import LoadScopeScheduling

    class Groups(LoadScopeScheduling):
        """xdist's scheduling by scope (the largest first), the scopes :func:`worker_group`'s."""

        def _split_scope(self, nodeid: str) -> str:
            return worker_group(nodeid) or nodeid

    return Groups(config, log)


def pytest_collection_modifyitems(config, items):
    slow = pytest.mark.slow
    for item in items:
        folder = item.path.parent.name
        if item.path.suffix == ".ipynb" or item.path.name in SLOW_MODULES or folder in SLOW_FOLDERS:
            item.add_marker(slow)
        callspec = getattr(item, "callspec", None)
        way = callspec.params.get("autograder") if callspec else None
        if way and worker_group(item.nodeid) != f"grading-{way}":  # the id must say its way
            raise pytest.UsageError(f"{item.nodeid}: graded {way}, grouped as another way")

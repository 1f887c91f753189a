"""The student release: the package with the solutions taken out, visible tests, scenes.

    python -m raykit_grading release -o student-release/

writes a folder students can ``pip install -e`` and test with ``python -m pytest``:

* ``raykit/``: every ``# BEGIN SOLUTION`` region replaced by a NotImplementedError with its
  hint (:mod:`raykit_grading.assignment.markers`); everything else as in the solution.
* ``scenes/``: the example scenes and their textures.
* ``tests/``: the visible grading tests, each with its inputs and the reference results (and,
  for renders, the reference image as a PNG to look at), checked by the same task code and
  comparison the grader uses (copied in as ``tests/_grading``).
* ``README.md``: what to write, how to test, how to submit.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np

from raykit.io.images import quantize, save_image
from raykit_grading import kit
from raykit_grading.assignment.catalog import (
    REPO,
    STAGE1,
    STAGE2,
    STAGE3,
    STAGE4,
    STAGE5,
    TESTS,
    VISIBLE,
)
from raykit_grading.assignment.markers import strip_solutions
from raykit_grading.assignment.references import array_mistakes, expected
from raykit_grading.kit import tasks
from raykit_grading.kit.cases import located

VISIBLE_TESTS = '''"""The visible grading tests: your functions against the reference results.

Each folder in expected/ holds one test: task.json (what to run), inputs.npz, expected.npz
(the reference results) and, for renders, reference.png. The grader runs the same tasks and
comparisons, in a sandbox, plus hidden tests.
"""

import json
from pathlib import Path

import numpy as np
import pytest
from _grading.cases import read_case
from _grading.tasks import TASKS
from _grading.compare import check_arrays, compare_images

from raykit.io.images import quantize

EXPECTED = Path(__file__).parent / "expected"
CASES = sorted(p.name for p in EXPECTED.iterdir() if p.is_dir())


def _what(case: str) -> str:
    """The test's id: its number and what it checks (``2.1 ray-plane hits``)."""
    return json.loads((EXPECTED / case / "task.json").read_text())["name"]


@pytest.mark.parametrize("case", CASES, ids=[_what(case) for case in CASES])
def test_visible(case):
    folder = EXPECTED / case
    order, arrays, want = read_case(folder)
    got = {k: np.asarray(v) for k, v in TASKS[order["task"]](order["spec"], arrays).items()}
    if order["kind"] == "image":
        mine, reference = quantize(got["rgb"]), quantize(want["rgb"])
        assert mine.shape == reference.shape, f"shape {mine.shape}, expected {reference.shape}"
        fraction = compare_images(mine, reference).fraction
        assert fraction >= 0.995, f"{fraction:.2%} of pixels match {folder / 'reference.png'}"
    else:
        passed, message = check_arrays(got, want)
        assert passed, message
'''

STUDENT_README = """# raykit: the starter kit

You write the lecture's functions; everything around them is given. Each function below raises
`NotImplementedError` with a hint until you write it. They come stage by stage, in the
lecture's order; the grading tests are numbered by the same stages (test 3.6 is stage 3's):

{functions}

## Set up and test

```bash
pip install -e ".[test]"
python -m pytest
```

`python -m pytest` prints one line for each test that fails, saying why; for the whole
traceback of one, run it alone with `python -m pytest --tb=short -k 3.6`.

The tests in `tests/` are the visible grading tests: your functions' results against the
reference, within a stated tolerance, and your renders against the reference images in
`tests/expected/*/reference.png` (a pixel counts as right when it is within 2 levels of the
reference pixel or one of its neighbours).

**These are practice tests.** The grader runs the same kinds of test on inputs of its own (new
random rays and sizes, the scenes seen from a slightly moved camera), drawn from a secret seed:
the same inputs for everyone and every time it grades, so grading again gives the same score.
There are hidden tests too. Code that only reproduces these expected results scores nothing;
code that computes them right passes both. A render that shows a classic mistake (such as rays
through pixel corners instead of centres) loses that test's points even when it looks close.

Before you submit, run the self-check: `python check.py` (or one test: `python check.py 3.6`;
a stage's tests: `python check.py 3`; `python check.py --help` says more). It runs the
practice tests with the grader's own comparison and its diagnosis of the classic mistakes,
and writes a captioned picture of each render (yours | expected | where they differ) and
`check/index.html` with all of them: open it in a browser.

Look at your pictures as you go: `raykit render scenes/classic.json -o classic.png`,
`raykit scan scenes/linescan/slide.json -o strip.png --diagram rays.png`.

## Submit

Upload your `raykit/` folder: the folder itself (the one that holds `__init__.py`, `camera.py`
and its subfolders), or a zip of it with `raykit/` at the zip's top. To make the zip, run this
in the folder that holds `raykit/` (this one):

```bash
{zip_command}
```

Only `raykit/` is graded; the tests, scenes and pictures need not be uploaded. Not the files
inside `raykit/` one by one: they score nothing, as the grader needs the folder. The grader's
results say in a line where it found `raykit/` when it was not at the top, or what it found
instead.
"""


# how students zip their work: Python's own zip tool, there wherever the kit runs
ZIP_COMMAND = "python -m zipfile -c raykit.zip raykit"

# the student README lists the functions to write in the lecture's order, stage by stage
LECTURE_STAGES = {
    STAGE1: ["linescan/camera.py", "linescan/objects.py"],
    STAGE2: ["planes.py", "spheres.py: sphere_roots", "spheres.py: hit_sphere", "hits.py"],
    STAGE3: ["camera.py", "billboards.py", "render.py"],
    STAGE4: ["spheres.py: sphere_normals", "lights.py: toward_light", "shading.py", "shadows.py",
             "mirrors.py"],
    # FOCG 13.4's order: in the pixel, soft shadows, depth of field, glossy, motion blur
    STAGE5: ["sampling.py: point_in_pixel", "sampling.py: random_set", "sampling.py: jittered",
             "sampling.py: point_on_parallelogram", "lights.py: sampled",
             "sampling.py: point_on_disk", "sampling.py: point_on_lens",
             "camera.py: thin_lens_rays", "sampling.py: basis_around",
             "sampling.py: perturbed_direction", "mirrors.py: glossy_reflect",
             "sampling.py: shutter_times", "spheres.py: center_at", "sampling.py"],
}  # fmt: skip
LECTURE_ORDER = [key for keys in LECTURE_STAGES.values() for key in keys]


def _lecture_order(function: str) -> int:
    """Where ``raykit/<module>: <function>`` comes in the lecture (unknown ones last): a key
    naming the function wins over one naming only its module (``camera.py: thin_lens_rays``
    is stage 5's, the rest of ``camera.py`` stage 3's)."""
    matching = [
        (len(key), i) for i, key in enumerate(LECTURE_ORDER) if function.startswith(f"raykit/{key}")
    ]
    return max(matching)[1] if matching else len(LECTURE_ORDER)


def _by_stage(functions: list[str]) -> str:
    """The README's list: a heading per stage (as the grading tests name them), its functions
    in the lecture's order."""
    stage_of = {key: stage for stage, keys in LECTURE_STAGES.items() for key in keys}
    grouped: dict[str, list[str]] = {}
    for name in sorted(functions, key=_lecture_order):
        index = _lecture_order(name)
        stage = f"Stage {stage_of[LECTURE_ORDER[index]]}" if index < len(LECTURE_ORDER) else "More"
        grouped.setdefault(stage, []).append(f"- `{name}`")
    return "\n\n".join(f"### {stage}\n\n" + "\n".join(lines) for stage, lines in grouped.items())


# what ships to students is raykit_grading/kit/ as it is: its self-check as check.py, the rest
# as tests/_grading/ (the name they import each other by there)
KIT = Path(kit.__file__).parent
SELF_CHECK = "selfcheck.py"


def kit_modules() -> list[Path]:
    """The kit's modules that the release copies into ``tests/_grading/``."""
    return sorted(p for p in KIT.glob("*.py") if p.name not in ("__init__.py", SELF_CHECK))


# the compiled engine repeats the solutions in machine code: students render with their own
NOT_RELEASED = {REPO / "raykit/engine/compiled"}  # the package, and all in it


def build_release(out: Path, progress=None) -> list[str]:
    """Build the release in ``out`` (which must not exist); returns the stubbed functions.
    ``progress(test)`` is called as each visible test's references are made (the long part:
    each render, and the classic mistakes' pictures)."""
    out = Path(out)
    if out.exists():
        raise FileExistsError(f"{out} exists; give a new folder")
    stubbed: list[str] = []
    for source in sorted((REPO / "raykit").rglob("*")):
        if "__pycache__" in source.parts or source.is_dir() or NOT_RELEASED & {*source.parents}:
            continue
        target = out / source.relative_to(REPO)
        target.parent.mkdir(parents=True, exist_ok=True)
        if source.suffix == ".py":
            text, names = strip_solutions(source.read_text(), str(source))
            target.write_text(text)
            stubbed += [f"{source.relative_to(REPO)}: {n}" for n in names]
        else:
            shutil.copy(source, target)
    shutil.copytree(
        REPO / "scenes",
        out / "scenes",
        ignore=shutil.ignore_patterns("__pycache__", "make_textures.py"),
    )
    (out / "pyproject.toml").write_text(_student_pyproject())
    _visible_tests(out / "tests", progress)
    shutil.copy(KIT / SELF_CHECK, out / "check.py")
    functions = _by_stage(stubbed)
    readme = STUDENT_README.format(functions=functions, zip_command=ZIP_COMMAND)
    (out / "README.md").write_text(readme)
    print(
        f"wrote {out}: {len(stubbed)} functions to write, "
        f"{sum(t.visibility == VISIBLE for t in TESTS)} visible tests"
    )
    return stubbed


STUDENT_PYPROJECT = """[build-system]
requires = ["setuptools>=64"]
build-backend = "setuptools.build_meta"

[project]
name = "raykit"
version = "{version}"
description = "raykit, the starter kit: the ray-tracing lecture's functions, for you to write"
requires-python = ">=3.10"
dependencies = {dependencies}

[project.optional-dependencies]
test = ["pytest>=7.4"]

[project.scripts]
raykit = "raykit.cli:main"

[tool.setuptools.packages.find]
include = ["raykit*"]

[tool.setuptools.package-data]
raykit = ["io/schemas/*.json"]

[tool.pytest.ini_options]
testpaths = ["tests"]
# one line for each failing test (its name and why); --tb=short for the traceback
addopts = "--tb=no -rf"
"""


def _student_pyproject() -> str:
    """What the release uses and nothing more: raykit's own dependencies, pytest for its
    tests (no notebooks, no lint rules for files it does not ship, no grader)."""
    import re

    text = (REPO / "pyproject.toml").read_text()
    version = re.search(r'^version = "([^"]+)"', text, re.M).group(1)
    dependencies = re.search(r"^dependencies = (\[[^\]]*\])", text, re.M).group(1)
    return STUDENT_PYPROJECT.format(version=version, dependencies=dependencies)


def _visible_tests(tests: Path, progress=None) -> None:
    helpers = tests / "_grading"
    helpers.mkdir(parents=True)
    (helpers / "__init__.py").write_text("")
    for module in kit_modules():
        shutil.copy(module, helpers / module.name)
    (tests / "test_visible.py").write_text(VISIBLE_TESTS)
    (tests / "conftest.py").write_text(
        "import sys\nfrom pathlib import Path\n\nsys.path.insert(0, str(Path(__file__).parent))\n"
    )
    for test in TESTS:
        if test.visibility != VISIBLE:
            continue
        folder = tests / "expected" / test.name.split()[0].replace(".", "_")
        folder.mkdir(parents=True)
        spec, arrays, files = test.public_inputs()
        for relative, source in files.items():
            (folder / relative).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy(source, folder / relative)
        callees = _callees(test, spec, arrays, folder)
        order = {"task": test.task, "kind": test.kind, "name": test.name, "spec": spec,
                 "points": test.points, "callees": callees}  # fmt: skip
        (folder / "task.json").write_text(json.dumps(order, indent=1))
        np.savez(folder / "inputs.npz", **arrays)
        want = tasks.TASKS[test.task](located(spec, folder), arrays)
        np.savez(folder / "expected.npz", **{k: np.asarray(v) for k, v in want.items()})
        if test.kind == "image":
            save_image(quantize(want["rgb"]), folder / "reference.png")
        if test.mistakes:  # the classic mistakes' pictures, for the self-check's diagnosis
            _mistake_pictures(test, quantize(want["rgb"]), folder)
        if test.kind != "image":  # and their results, for the array tests
            _mistake_results(test, want, folder)
        if progress:
            progress(test)


def _callees(test, spec: dict, arrays: dict, folder: Path) -> list[dict]:
    """The functions the test's function calls, each with its inputs (``callees/<name>.npz``:
    ``in_`` arrays) and the reference's results (``out_`` arrays), for the self-check to say
    where a difference starts."""
    found = []
    for callee in test.callees:
        their_spec, their_arrays = callee.inputs(spec, arrays)
        want = tasks.TASKS[callee.task](json.loads(json.dumps(their_spec)), their_arrays)
        (folder / "callees").mkdir(exist_ok=True)
        np.savez(
            folder / "callees" / f"{callee.name}.npz",
            **{f"in_{k}": v for k, v in their_arrays.items()},
            **{f"out_{k}": np.asarray(v) for k, v in want.items()},
        )
        found.append({"name": callee.name, "task": callee.task, "spec": their_spec})
    return found


def _mistake_pictures(test, right: np.ndarray, folder: Path) -> None:
    from raykit_grading.assignment.mistakes import MISTAKES

    says = {}
    (folder / "mistakes").mkdir()
    for mistake in MISTAKES:
        if not (mistake.in_renders and mistake.tried_on(test.stage)):
            continue
        wrong = quantize(expected(test.name, None, mistake.key)["rgb"])
        if not np.array_equal(wrong, right):  # only the mistakes that change this picture
            save_image(wrong, folder / "mistakes" / f"{mistake.key}.png")
            says[mistake.key] = {"says": mistake.says, "where": mistake.where}
    (folder / "mistakes.json").write_text(json.dumps(says, indent=1))


def _mistake_results(test, want: dict, folder: Path) -> None:
    """``mistakes/<key>.npz``: the results of each classic mistake that changes this array
    test's results, and ``mistakes.json`` saying what each is."""
    from raykit_grading.assignment.mistakes import MISTAKES
    from raykit_grading.kit.compare import judge_arrays

    says = {}
    where = {m.says: m for m in MISTAKES}
    for text, results, _ in array_mistakes(test, None):
        if judge_arrays(results, {k: np.asarray(v) for k, v in want.items()}).share >= 1.0:
            continue  # this mistake changes nothing here
        mistake = where[text]
        (folder / "mistakes").mkdir(exist_ok=True)
        np.savez(folder / "mistakes" / f"{mistake.key}.npz", **results)
        says[mistake.key] = {"says": mistake.says, "where": mistake.where}
    (folder / "mistakes.json").write_text(json.dumps(says, indent=1))

"""The grader laid out by where its code runs (raykit_grading/__init__.py): what ships to
students imports nothing else of the grader, what runs inside the sandbox nothing of it, each
subpackage only those below it, and every module is in the index and in docs/layout.md and has
a test file of its name, laid out as the grader is."""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

from conftest import REPO

GRADER = REPO / "raykit_grading"
# bottom to top: each may import the ones before it, never one after it
ROLES = ("kit", "inside", "sandbox", "assignment", "grading", "platforms")
# what the kit may import besides the standard library: what students install, and its own
# modules by the name they have in the kit (tests/_grading/)
KIT_MAY_IMPORT = {"numpy", "PIL", "raykit", "pytest", "_grading"}


def imported(path: Path) -> list[tuple[str, int]]:
    """(module, line) of every import in ``path``, wherever it stands (a function's too), and
    of every name imported from a module (``module.name``); relative imports made absolute."""
    package = ".".join(path.relative_to(path.parents[2]).parts[:-1])  # raykit_grading.<role>
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found += [(alias.name, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parts = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*parts, *([base] if base else [])])
            found.append((base, node.lineno))
            found += [(f"{base}.{alias.name}", node.lineno) for alias in node.names]
    return found


def modules(role: str) -> list[Path]:
    return sorted((GRADER / role).glob("*.py"))


def kit_problems(path: Path, shipped: set[str]) -> list[str]:
    """What in a module of the kit would not run in the starter kit: an import of anything
    but the standard library, what students install, and the kit's ``shipped`` modules."""
    problems = []
    for name, line in imported(path):
        top = name.split(".")[0]
        if top == "_grading" and name.count(".") and name.split(".")[1] not in shipped:
            problems.append(f"{path.name}:{line}: {name} (not in the kit)")
        elif top not in KIT_MAY_IMPORT and top not in sys.stdlib_module_names:
            problems.append(f"{path.name}:{line}: {name}")
    return problems


def test_the_kit_imports_nothing_else_of_the_grader():
    shipped = {p.stem for p in modules("kit")}
    problems = [p for path in modules("kit") for p in kit_problems(path, shipped)]
    assert not problems, f"the kit imports what students do not have: {problems}"


def test_the_kit_check_fails_on_an_import_of_the_sandbox(tmp_path):
    """The check above can fail: a kit module that imports the sandbox, or a grader module
    by its kit name, is caught."""
    kit = tmp_path / "raykit_grading" / "kit"
    kit.mkdir(parents=True)
    (kit / "compare.py").write_text(
        "import numpy as np\nfrom raykit_grading.sandbox.base import Limits\n"
        "from _grading.catalog import TESTS\n"
    )
    found = kit_problems(kit / "compare.py", {"compare", "cases", "tasks", "selfcheck"})
    assert [p.split(": ")[1].split(" ")[0] for p in found] == [
        "raykit_grading.sandbox.base",
        "raykit_grading.sandbox.base.Limits",
        "_grading.catalog",
        "_grading.catalog.TESTS",
    ]


def test_the_release_ships_the_kit_as_it_is():
    """The release copies the kit folder: a module added to it ships, and nothing else does."""
    from raykit_grading.assignment.release import KIT, SELF_CHECK, kit_modules

    assert KIT == GRADER / "kit"
    shipped = {p.name for p in kit_modules()} | {SELF_CHECK, "__init__.py"}
    assert shipped == {p.name for p in modules("kit")}


def test_what_runs_inside_the_sandbox_imports_nothing_of_the_grader():
    """The child runs with ``-I -S`` where the grader is not: the standard library and numpy
    only (the tasks it loads by path, from the kit)."""
    problems = [
        f"{path.name}:{line}: {name}"
        for path in modules("inside")
        for name, line in imported(path)
        if name.split(".")[0] not in {"numpy"} and name.split(".")[0] not in sys.stdlib_module_names
    ]
    assert not problems


@pytest.mark.parametrize("role", ROLES)
def test_each_role_imports_only_the_roles_below_it(role):
    allowed = {f"raykit_grading.{r}" for r in ROLES[: ROLES.index(role) + 1]}
    problems = [
        f"{path.relative_to(GRADER)}:{line}: {name}"
        for path in modules(role)
        for name, line in imported(path)
        if name.startswith("raykit_grading")
        and name != "raykit_grading"
        and ".".join(name.split(".")[:2]) not in allowed
    ]
    assert not problems, f"{role} reaches up: {problems}"


def test_every_module_is_in_the_index_and_the_layout_page():
    import raykit_grading

    index = raykit_grading.__doc__
    layout = (REPO / "docs" / "layout.md").read_text()
    missing = []
    for role in ROLES:
        row = next(line for line in layout.splitlines() if f"`raykit_grading/{role}/`" in line)
        for path in modules(role):
            if path.name == "__init__.py":
                continue
            if f"raykit_grading.{role}.{path.stem}`" not in index:
                missing.append(f"the index: {role}/{path.name}")
            if f"`{path.stem}`" not in row:
                missing.append(f"docs/layout.md: {role}/{path.name}")
    assert not missing
    assert {p.name for p in GRADER.iterdir() if p.suffix == ".py"} == {"__init__.py", "__main__.py"}


def test_every_module_has_a_test_file_of_its_name_and_every_test_file_a_module():
    """tests/grading/<role>/test_<module>.py for each module of raykit_grading/<role>/ (and
    __main__.py's in tests/grading/test_main.py), as docs/layout.md says."""
    tests = REPO / "tests" / "grading"
    wanted = {
        f"{role}/test_{p.stem}.py" for role in ROLES for p in modules(role) if p.stem != "__init__"
    }
    found = {
        p.relative_to(tests).as_posix() for role in ROLES for p in (tests / role).glob("test_*.py")
    }
    assert (sorted(wanted - found), sorted(found - wanted)) == ([], [])
    assert (tests / "test_main.py").is_file()

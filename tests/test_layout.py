"""The tree is the architecture: the lecture's math at the top of raykit/, the engine's speed in
raykit/engine/, input and output in raykit/io/; and the imports keep to it.

    python tests/test_layout.py      prints how many imports run between the wings

Imports are read with ``ast`` (every ``import`` and ``from ... import`` anywhere in a module,
including inside functions), not by importing anything.
"""

from __future__ import annotations

import ast
import sys
from collections import Counter
from pathlib import Path

RAYKIT = Path(__file__).resolve().parent.parent / "raykit"

# the lecture's math: what students read and write, and what everything else stands on
MATH = {
    "rays", "planes", "spheres", "billboards", "camera", "hits", "scene", "lights", "materials",
    "surfaces", "shading", "shadows", "mirrors", "sampling",
    "linescan.camera", "linescan.objects", "linescan.scene", "linescan.scan",
}  # fmt: skip
# the top: the lecture's loops (image order, object order, forward), their figures and the
# command line, which put the wings together
TOP = {
    "render", "object_order", "forward", "pinhole", "cli", "__main__", "__init__",
    "linescan.__init__", "linescan.diagrams", "linescan.sweep3d",
}  # fmt: skip


def wing(module: str) -> str:
    """``math``, ``engine``, ``io``, ``diagrams`` or ``top`` for a module name under raykit."""
    if module.startswith(("engine.", "io.")) or module in ("engine", "io"):
        return module.split(".")[0]
    if module.startswith("diagrams"):
        return "diagrams"
    if module in MATH:
        return "math"
    if module in TOP:
        return "top"
    raise AssertionError(f"raykit.{module} belongs to no wing: add it to tests/test_layout.py")


def modules() -> dict[str, Path]:
    found = {}
    for path in sorted(RAYKIT.rglob("*.py")):
        name = ".".join(path.relative_to(RAYKIT).with_suffix("").parts)
        found[name] = path
    return found


def raykit_imports(path: Path) -> list[str]:
    """The raykit modules ``path`` imports (names under raykit, without the prefix)."""
    names = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            names += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module == "raykit":  # from raykit import x
                names += [f"raykit.{alias.name}" for alias in node.names]
            else:
                names.append(node.module)
    return [name.removeprefix("raykit.") for name in names if name.startswith("raykit.")]


def between_wings() -> Counter:
    """How many imports run from each wing to each other wing: ``{(from, to): count}``."""
    counts: Counter = Counter()
    for name, path in modules().items():
        for target in raykit_imports(path):
            counts[(wing(name), wing(target))] += 1
    return counts


def test_every_module_belongs_to_a_wing_and_the_top_holds_no_engine_or_io():
    wings = {name: wing(name) for name in modules()}
    top_level = {name for name in wings if "." not in name}
    engine_or_io = {"tiles", "screen_bounds", "pairs", "boxes", "bvh", "adaptive", "precision",
                    "fields", "errors", "textures", "images", "nff"}  # fmt: skip
    assert not top_level & engine_or_io
    assert wings["engine.tiles"] == "engine" and wings["io.scene_json"] == "io"


def test_the_math_imports_nothing_from_the_engine_or_io():
    offences = [
        f"raykit.{name} imports raykit.{target}"
        for name, path in modules().items()
        if wing(name) == "math"
        for target in raykit_imports(path)
        if wing(target) not in ("math",)
    ]
    assert offences == []


def test_the_engine_imports_only_the_math_and_itself():
    offences = [
        f"raykit.{name} imports raykit.{target}"
        for name, path in modules().items()
        if wing(name) == "engine"
        for target in raykit_imports(path)
        if wing(target) not in ("math", "engine")
    ]
    assert offences == []


def test_io_builds_the_lectures_objects_and_uses_no_engine():
    offences = [
        f"raykit.{name} imports raykit.{target}"
        for name, path in modules().items()
        if wing(name) == "io"
        for target in raykit_imports(path)
        if wing(target) not in ("math", "io")
    ]
    assert offences == []


def test_the_import_reader_sees_imports_inside_functions(tmp_path):
    module = tmp_path / "m.py"
    module.write_text("def f():\n    from raykit.engine.tiles import TILE\n    import raykit.io\n")
    assert raykit_imports(module) == ["engine.tiles", "io"]


if __name__ == "__main__":
    for (source, target), count in sorted(between_wings().items()):
        if source != target:
            print(f"{source:>8} -> {target:<8} {count}")
    sys.exit(0)

"""The twin table (raykit.engine.compiled.twins) holds: every kernel is in it once, every row
names a kernel and a reference function that exist, a twin keeps its reference's name and file
stem unless the row says why, every function of the lecture's modules that the numpy engine runs
has a twin (or is shared), every row has its differential check in its module's test file, and
the documentation names each twin while the student release never does."""

from __future__ import annotations

import importlib
import sys
from dataclasses import replace

import pytest

from conftest import REPO, SCENES
from raykit.engine import compiled
from raykit.engine.compiled import twins
from raykit.io.scene_json import load_scene
from raykit.render import render

from .harness import kernels, resolve

# the lecture's modules: the reference functions a student writes and the renderer's loop
LECTURE = {
    f"raykit.{name}"
    for name in (
        "rays planes spheres billboards camera hits lights surfaces shading shadows mirrors render"
        " sampling"
    ).split()
}


def test_every_kernel_is_a_twin_or_the_engines_own_once():
    in_table = [twin.kernel for twin in twins.TWINS] + list(twins.OWN)
    assert len(in_table) == len(set(in_table)), "a kernel in the table twice"
    found = set(kernels())
    assert found == set(in_table), (
        f"kernels with no row: {sorted(found - set(in_table))}; "
        f"rows with no kernel: {sorted(set(in_table) - found)}"
    )


def test_every_reference_function_named_exists():
    names = [twin.reference for twin in twins.TWINS]
    names += list(twins.WITHIN) + list(twins.EVERYWHERE)
    for name in names:
        assert callable(resolve(name)), name
    for kernel in twins.WITHIN.values():
        assert kernel in kernels(), kernel


@pytest.mark.parametrize("twin", twins.TWINS, ids=lambda twin: twin.kernel)
def test_a_twin_keeps_its_references_name_and_file_stem_unless_the_table_says_why(twin):
    stem, name = twin.kernel.split(".")
    parts = twin.reference.split(".")
    reference_name = parts[-1]
    reference_stem = next(part for part in reversed(parts[:-1]) if not part[0].isupper())
    if not twin.why:
        assert (stem, name) == (reference_stem, reference_name), (
            f"{twin.kernel} repeats {twin.reference}: name it so, or say why not in the table"
        )
    else:
        assert (stem, name) != (reference_stem, reference_name), "a reason with nothing to explain"


def _calls(run) -> set[str]:
    """The functions of the lecture's modules that ``run()`` calls, by full dotted name."""
    called = set()

    def profile(frame, event, arg):
        if event == "call":
            module = frame.f_globals.get("__name__", "")
            name = frame.f_code.co_qualname
            if module in LECTURE and "<" not in name and not name.split(".")[-1].startswith("__"):
                called.add(f"{module}.{name}")

    sys.setprofile(profile)
    try:
        run()
    finally:
        sys.setprofile(None)
    return called


def test_every_lecture_function_the_numpy_engine_runs_has_a_twin_or_is_shared():
    def scenes():  # each run its own: a scene caches what it computes once (its camera frame)
        for name in ("classic", "classic_lit", "mirror_balls", "cutouts", "shadow_on_billboard",
                     "soft_shadows", "depth_of_field", "glossy", "motion_blur"):  # fmt: skip
            scene = load_scene(SCENES / f"{name}.json")
            yield replace(scene, camera=replace(scene.camera, width=24, height=16))

    def samples(scene):  # a distributed scene takes its own
        return 1 if scene.distributed else 2

    numpy_calls = _calls(lambda: [render(s, samples(s), engine="numpy") for s in scenes()])
    # what the compiled engine runs itself, in Python, as it prepares a scene: shared, not copied
    shared = _calls(lambda: [compiled.render.render(s, samples(s)) for s in scenes()])
    # properties and methods of the scene's classes are its data, read by both engines
    shared |= {name for name in numpy_calls if resolve(name) is None}
    twinned = {twin.reference for twin in twins.TWINS} | set(twins.WITHIN) | set(twins.EVERYWHERE)
    alone = numpy_calls - shared - twinned
    assert not alone, f"run by the numpy engine, with no compiled twin in the table: {alone}"
    assert {"raykit.shading.blinn_phong", "raykit.render.cast"} <= numpy_calls
    stage_5 = {"raykit.lights.sampled", "raykit.sampling._cos_sin", "raykit.mirrors.glossy_reflect",
               "raykit.sampling.shutter_times", "raykit.spheres.center_at"}  # fmt: skip
    assert stage_5 <= numpy_calls


@pytest.mark.parametrize("twin", twins.TWINS, ids=lambda twin: twin.kernel)
def test_every_twin_has_a_differential_check_in_its_modules_test_file(twin):
    stem = twin.kernel.split(".")[0]
    tests = importlib.import_module(f"{__package__}.test_{stem}")
    assert twin.kernel in tests.CHECKS, (
        f"tests/compiled/test_{stem}.py: CHECKS has no {twin.kernel}"
    )


def test_the_documentation_names_each_reference_functions_twin():
    conf = (REPO / "docs/conf.py").read_text()
    assert "doc_lines" in conf and "autodoc-process-docstring" in conf  # the hook adds these
    (line,) = twins.doc_lines("raykit.spheres.hit_sphere")
    assert ":func:`raykit.engine.compiled.spheres.hit_sphere`" in line
    assert "tests/compiled/test_spheres.py" in line
    assert "why" not in line and "(" not in line.split("tested")[0]  # same name: no reason
    (line,) = twins.doc_lines("raykit.lights.toward_light")
    assert "toward_point_light` (a point light's only" in line
    assert len(twins.doc_lines("raykit.shading.surface_color")) == 3  # one kernel, two in lanes
    (line,) = twins.doc_lines("raykit.spheres.sphere_roots")
    assert "repeated inside :func:`raykit.engine.compiled.spheres.hit_sphere`" in line
    assert twins.doc_lines("raykit.camera.camera_frame") == []


def test_the_student_release_holds_no_twin_line(tmp_path):
    from raykit_grading.assignment.release import build_release

    build_release(tmp_path / "kit")
    shipped = [path for path in (tmp_path / "kit").rglob("*") if path.is_file()]
    assert any(path.name == "spheres.py" for path in shipped)
    for path in shipped:
        if path.suffix in (".py", ".md", ".txt", ".toml", ".json"):
            text = path.read_text()
            assert "Compiled twin" not in text, path

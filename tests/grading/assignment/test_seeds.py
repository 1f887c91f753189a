"""One secret seed per assignment: the same graded inputs on every grading, every command,
every machine.

A regrade must not change a grade: the graded inputs come from the assignment's seed file
(raykit_grading/assignment/seeds.py), which every command finds in the assignment folder, the draw
is the same on any processor and thread count, and results.json names the seed by a fingerprint
only."""

import ast
import hashlib
import json
import os
import shutil
import stat
import subprocess
import sys
import zipfile

import numpy as np
import pytest

from conftest import REPO
from mistaken_submissions import make_submission
from raykit_grading.assignment.catalog import TESTS, VISIBLE
from raykit_grading.assignment.seeds import (
    HEADER,
    SeedFileError,
    assignment_seed,
    find_assignment,
    fingerprint,
    read_seed_file,
    seed_from_file,
)
from raykit_grading.grading.grade import Options, grade

SEED = 20261126


def draw_digest(seed: int) -> str:
    """sha256 of every test's graded inputs under ``seed``: spec, arrays (dtype, shape, bytes),
    the files handed to the child."""
    digest = hashlib.sha256()
    for test in TESTS:
        spec, arrays, files = test.graded_inputs(seed)
        digest.update(test.name.encode())
        digest.update(json.dumps(spec, sort_keys=True).encode())
        for key in sorted(arrays):
            array = np.ascontiguousarray(arrays[key])
            digest.update(f"{key} {array.dtype} {array.shape}".encode())
            digest.update(array.tobytes())
        digest.update(json.dumps(sorted((k, v.name) for k, v in files.items())).encode())
    return digest.hexdigest()


HERE_SUPPORT_TESTS = ("grading/assignment", "support", "")  # this module, its helpers, conftest
DIGEST_IN_A_CHILD = f"""
import json
import sys

sys.path[:0] = {[str(REPO / "tests" / f) for f in HERE_SUPPORT_TESTS] + [str(REPO)]!r}
from numpy._core import _multiarray_umath as umath
from test_seeds import draw_digest

on = [f for f in umath.__cpu_dispatch__ if umath.__cpu_features__.get(f)]
print(json.dumps({{"digest": draw_digest({SEED}), "dispatched": on}}))
"""


def _digest_under(env: dict) -> dict:
    run = subprocess.run(
        [sys.executable, "-c", DIGEST_IN_A_CHILD],
        env={**os.environ, **env},
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(run.stdout)


def test_the_graded_draw_is_the_same_without_simd_and_on_any_thread_count():
    """The same seed gives the same inputs bit for bit with numpy's vector extensions turned
    off (AVX-512 and AVX2 on x86: a Gradescope machine of an older processor) and with one or
    two BLAS threads."""
    from numpy._core import _multiarray_umath as umath

    here = draw_digest(SEED)
    dispatched = [f for f in umath.__cpu_dispatch__ if umath.__cpu_features__.get(f)]
    plain = _digest_under(
        {"NPY_DISABLE_CPU_FEATURES": " ".join(dispatched), "OPENBLAS_NUM_THREADS": "1"}
    )
    assert plain["dispatched"] == []  # the extensions really were off in that run
    assert plain["digest"] == here
    threaded = _digest_under({"OPENBLAS_NUM_THREADS": "2", "OMP_NUM_THREADS": "2"})
    assert threaded == {"digest": here, "dispatched": dispatched}


# what may differ in its last bits from one processor (or BLAS, or thread count) to another
MACHINE_DEPENDENT = {
    "dot", "matmul", "inner", "vdot", "tensordot", "einsum", "norm",
    "sin", "cos", "tan", "arcsin", "arccos", "arctan", "arctan2", "sinh", "cosh", "tanh",
    "exp", "exp2", "expm1", "log", "log2", "log10", "log1p", "power", "cbrt", "hypot",
}  # fmt: skip


def test_the_draw_uses_no_blas_and_no_vectorised_transcendental_functions():
    """catalog.py draws the inputs: no ``@``, no np.dot / np.linalg.norm / np.sin ... in it
    (raykit.rays.dot and normalize sum left to right; np.sqrt is correctly rounded)."""
    tree = ast.parse((REPO / "raykit_grading/assignment/catalog.py").read_text())
    found = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.BinOp, ast.AugAssign)) and isinstance(node.op, ast.MatMult):
            found.append(f"line {node.lineno}: @")
        if isinstance(node, ast.Attribute) and node.attr in MACHINE_DEPENDENT:
            root = node.value
            while isinstance(root, ast.Attribute):
                root = root.value
            if isinstance(root, ast.Name) and root.id in ("np", "numpy"):
                found.append(f"line {node.lineno}: np...{node.attr}")
    assert found == []


def test_different_seeds_draw_different_inputs_for_every_test():
    for test in TESTS:
        one, other = test.graded_inputs(1), test.graded_inputs(2)
        same_spec = json.dumps(one[0], sort_keys=True) == json.dumps(other[0], sort_keys=True)
        same_arrays = one[1].keys() == other[1].keys() and all(
            np.array_equal(one[1][k], other[1][k]) for k in one[1]
        )
        assert not (same_spec and same_arrays), test.name


# ---- the seed file ------------------------------------------------------------------------


def test_a_seed_file_is_made_once_with_mode_600_and_then_read(tmp_path):
    path = tmp_path / "grading-seed"
    seed, made = seed_from_file(path)
    assert made and stat.S_IMODE(path.stat().st_mode) == 0o600
    assert seed_from_file(path) == (seed, False)
    assert seed.bit_length() > 64  # too many seeds to try against the fingerprint
    assert str(seed) not in fingerprint(seed) and fingerprint(seed) == fingerprint(seed)
    assert fingerprint(seed) != fingerprint(seed + 1)
    assert list(tmp_path.iterdir()) == [path]  # no temporary left


def test_a_seed_file_others_can_read_is_made_private(tmp_path, capsys):
    path = tmp_path / "seed"
    path.write_text("# a comment\n12345\n")
    path.chmod(0o644)
    assert read_seed_file(path) == 12345
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert "was readable by others: made it mode 600" in capsys.readouterr().err


@pytest.mark.parametrize("text", ["", "12 13\n", "-4\n", "0x1f\n", "seed\n"])
def test_a_seed_file_that_holds_no_seed_is_refused_naming_it(tmp_path, text):
    path = tmp_path / "seed"
    path.write_text(text)
    with pytest.raises(SeedFileError, match=f"^{path}: not a grading seed"):
        read_seed_file(path)


# ---- the assignment folder -----------------------------------------------------------------


def _seed_file(folder, seed: int):
    """``folder/grading-seed`` holding ``seed``, as the commands make it."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "grading-seed"
    path.write_text(f"{HEADER}{seed}\n")
    path.chmod(0o600)
    return path


def test_the_assignment_seed_is_found_from_a_subfolder_as_git_finds_its_folder(
    tmp_path, monkeypatch
):
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    seed_file = _seed_file(tmp_path / "course/ray-tracing", 11)
    deep = tmp_path / "course/ray-tracing/graded/week-1"
    deep.mkdir(parents=True)
    monkeypatch.chdir(deep)
    assert find_assignment() == tmp_path / "course/ray-tracing"
    found = assignment_seed(make=True)
    assert (found.seed, found.file, found.made) == (11, seed_file, False)
    assert found.line() == f"raykit_grading: assignment seed {fingerprint(11)} ({seed_file})"
    assert list(deep.iterdir()) == []  # found: nothing made here


def test_the_search_stops_below_the_home_folder(tmp_path, monkeypatch):
    home = tmp_path / "home"
    _seed_file(home, 11)  # a seed lying in the home folder belongs to no assignment below it
    (home / "course").mkdir()
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(home / "course")
    assert find_assignment() is None
    with pytest.raises(SeedFileError, match=r"^no grading-seed in .*course or the folders above"):
        assignment_seed(make=False)
    monkeypatch.chdir(home)  # but the home folder itself is a folder to work in
    assert find_assignment() == home


def test_with_no_assignment_seed_one_is_made_in_the_current_folder_and_said_so(
    tmp_path, monkeypatch
):
    monkeypatch.setenv("HOME", str(tmp_path))
    (tmp_path / "a1").mkdir()
    monkeypatch.chdir(tmp_path / "a1")
    made = assignment_seed(make=True)
    assert made.made and made.file == tmp_path / "a1/grading-seed"
    assert stat.S_IMODE(made.file.stat().st_mode) == 0o600
    assert made.line() == (
        f"raykit_grading: assignment seed {made.fingerprint} (./grading-seed, made now, mode "
        "600: the commands run in this folder or below use it)"
    )
    assert assignment_seed(make=True) == type(made)(made.seed, made.file, made=False)


def test_assignment_seed_file_and_seed_override_the_search_in_that_order(tmp_path, monkeypatch):
    monkeypatch.setenv("HOME", str(tmp_path))
    _seed_file(tmp_path / "here", 1)
    _seed_file(tmp_path / "other", 2)
    monkeypatch.chdir(tmp_path / "here")
    assert assignment_seed(make=False).seed == 1
    assert assignment_seed(tmp_path / "other", make=False).seed == 2
    given = _seed_file(tmp_path / "given", 3)
    assert assignment_seed(tmp_path / "other", make=False, seed_file=given).seed == 3
    by_hand = assignment_seed(tmp_path / "other", make=False, seed_file=given, seed=4)
    assert (by_hand.seed, by_hand.file) == (4, None)
    assert by_hand.line() == f"raykit_grading: assignment seed {fingerprint(4)} (--seed)"
    with pytest.raises(SeedFileError, match="no/such: no such assignment folder"):
        assignment_seed(tmp_path / "no/such", make=True)
    with pytest.raises(SeedFileError, match="empty/grading-seed: no such seed file"):
        (tmp_path / "empty").mkdir()
        assignment_seed(tmp_path / "empty", make=False)


def test_try_zip_names_the_zips_seed_and_warns_when_it_is_not_the_assignments(
    tmp_path, monkeypatch, capsys
):
    from raykit_grading.platforms.containers import say_seeds
    from raykit_grading.platforms.gradescope import build_zip

    monkeypatch.setenv("HOME", str(tmp_path))
    archive = build_zip(tmp_path / "autograder.zip", 7)
    _seed_file(tmp_path / "same", 7)
    _seed_file(tmp_path / "other", 8)
    monkeypatch.chdir(tmp_path / "same")
    capsys.readouterr()
    say_seeds(archive, None)
    zipped = f"raykit_grading: assignment seed {fingerprint(7)} ({archive}: grading-seed)\n"
    assert capsys.readouterr().err == zipped
    say_seeds(archive, tmp_path / "other")
    assert capsys.readouterr().err == zipped + (
        f"raykit_grading: warning: the zip's seed {fingerprint(7)} is not this assignment's "
        f"{fingerprint(8)} ({tmp_path / 'other/grading-seed'}): grade and batch here grade on "
        "other inputs than the zip\n"
    )


def test_grade_refuses_a_bad_seed_file_in_one_line_before_grading(tmp_path, solution):
    (tmp_path / "seed").write_text("not a number\n")
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(solution),
         "-o", str(tmp_path / "out/results.json"), "--seed-file", str(tmp_path / "seed")],
        capture_output=True, text=True, cwd=REPO,
    )  # fmt: skip
    assert run.returncode == 2
    assert run.stderr == f"raykit_grading: error: {tmp_path / 'seed'}: not a grading seed " \
        "(expected one whole number >= 0)\n"  # fmt: skip
    assert not (tmp_path / "out").exists()


# ---- the same score every time ------------------------------------------------------------


@pytest.fixture(scope="module")
def borderline(tmp_path_factory):
    """Half right: the line-scan camera's samples a fifth of a pixel off centre (0.3 for 0.5),
    so test 1.6's scan matches at some camera positions and not at others."""
    folder = make_submission(tmp_path_factory.mktemp("borderline"))
    path = folder / "raykit/linescan/camera.py"
    right = "return -1.0 + (i + (k + 0.5) / samples) * (2.0 / pixels)"
    assert path.read_text().count(right) == 1
    path.write_text(path.read_text().replace(right, right.replace("0.5", "0.3")))
    return folder


def _grade_command(submission, results, *more, cwd):
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o", str(results),
         "--only", "1.5", "1.6", "1.7", *more],
        capture_output=True, text=True, cwd=cwd, env={**os.environ, "HOME": str(cwd)},
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    return json.loads(results.read_text()), run


def test_a_borderline_submission_scores_the_same_when_graded_again(borderline, tmp_path):
    first, run = _grade_command(borderline, tmp_path / "graded/results.json", cwd=tmp_path)
    seed_file = tmp_path / "grading-seed"  # the assignment folder's: the current folder's
    seed = read_seed_file(seed_file)
    assert stat.S_IMODE(seed_file.stat().st_mode) == 0o600
    assert f"assignment seed {fingerprint(seed)} (./grading-seed, made now, mode 600" in run.stderr
    again, run = _grade_command(borderline, tmp_path / "graded/results.json", cwd=tmp_path)
    assert f"assignment seed {fingerprint(seed)} (./grading-seed)\n" in run.stderr
    scores = [(t["number"], t["score"]) for t in first["tests"]]
    assert scores == [(t["number"], t["score"]) for t in again["tests"]]
    assert first["score"] == again["score"]
    assert first["extra_data"]["seed_fingerprint"] == fingerprint(seed)
    assert again["extra_data"]["seed_fingerprint"] == fingerprint(seed)
    assert str(seed) not in (tmp_path / "graded/results.json").read_text()
    # --seed overrides the file (and makes none), and repeats its own draw
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    by_hand, run = _grade_command(borderline, elsewhere / "r.json", "--seed", str(seed),
                                  cwd=elsewhere)  # fmt: skip
    assert [(t["number"], t["score"]) for t in by_hand["tests"]] == scores
    assert f"assignment seed {fingerprint(seed)} (--seed)\n" in run.stderr
    assert not (elsewhere / "grading-seed").exists()
    # --seed-file overrides the assignment's
    other = _seed_file(elsewhere / "other", seed + 1)
    _, run = _grade_command(borderline, elsewhere / "r.json", "--seed-file", str(other),
                            cwd=tmp_path)  # fmt: skip
    assert f"assignment seed {fingerprint(seed + 1)} (./elsewhere/other/grading-seed)\n" in (
        run.stderr
    )


def test_the_borderline_submission_is_borderline_its_score_depends_on_the_seed(
    borderline, child_python
):
    """Without one seed per assignment, its grade would change from run to run."""
    scores = {
        grade(borderline, names=["1.6"], seed=seed, options=Options(child_python))["score"]
        for seed in range(1, 9)
    }
    assert len(scores) > 1 and min(scores) < 2


def test_batch_grades_every_student_under_one_seed_and_refuses_to_mix_in_another(
    tmp_path, child_python, borderline, capsys
):
    from raykit_grading.grading.batch import grade_folder

    students = tmp_path / "submissions"
    for name in ("ada", "bob"):
        shutil.copytree(borderline, students / name)
    out = tmp_path / "out"
    options = Options(child_python)
    seed = read_seed_file(_seed_file(tmp_path, 20261127))
    assert grade_folder(students, out, names=["1.6"], options=options, assignment=tmp_path) == 0
    assert f"assignment seed {fingerprint(seed)} ({tmp_path / 'grading-seed'})" in (
        capsys.readouterr().err
    )

    def graded():
        return {
            name: json.loads((out / "feedback" / name / "results.json").read_text())
            for name in ("ada", "bob")
        }

    first = graded()
    assert {r["extra_data"]["seed_fingerprint"] for r in first.values()} == {fingerprint(seed)}
    assert first["ada"]["score"] == first["bob"]["score"]  # the same code, the same tests
    before = {n: (out / "feedback" / n / "results.json").stat().st_mtime_ns for n in first}
    assert grade_folder(students, out, names=["1.6"], options=options, assignment=tmp_path) == 0
    after = {n: (out / "feedback" / n / "results.json").stat().st_mtime_ns for n in first}
    assert after == before  # graded under this seed already: not graded again
    # under another seed, into the same folder: refused in one line, naming both
    shutil.copy(tmp_path / "grading-seed", out / "grading-seed")  # as a batch kept it before
    capsys.readouterr()
    assert grade_folder(students, out, names=["1.6"], options=options, seed=seed + 1) == 2
    refusal = capsys.readouterr().err.splitlines()[-1]
    assert refusal == (
        f"raykit_grading: error: {out} was graded under the seed {fingerprint(seed)}, this run's "
        f"is {fingerprint(seed + 1)}: grade into another folder, or --regrade to grade everyone "
        f"again under {fingerprint(seed + 1)}; its old seed is {out / 'grading-seed'}: "
        f"--seed-file {out / 'grading-seed'} keeps it"
    )
    assert graded() == first
    assert grade_folder(students, out, names=["1.6"], options=options, seed=seed + 1,
                        regrade=True) == 0  # fmt: skip
    regraded = graded()
    assert {r["extra_data"]["seed_fingerprint"] for r in regraded.values()} == {
        fingerprint(seed + 1)
    }


# ---- one assignment, one seed: every command grades alike -----------------------------------

# the borderline line-scan tests (test 1.6's score depends on the seed) and a ray-plane test
ONLY = ["1.5", "1.6", "1.7", "2.1"]


def test_run_autograder_grade_batch_and_prairielearn_score_a_submission_alike_with_no_seed_option(
    tmp_path, borderline, child_python, grader_python
):
    """The guide's commands as written, in the assignment folder: the release makes its seed,
    the zip and the PrairieLearn question carry it, and the zip's run_autograder, ``grade``
    (from a subfolder), ``batch`` (from elsewhere, with --assignment) and the PrairieLearn
    question's job grade a partly wrong submission test for test alike, each under that seed's
    fingerprint."""
    assignment = tmp_path / "ray-tracing"
    assignment.mkdir()
    home = {**os.environ, "HOME": str(tmp_path)}
    # and wrong whatever the seed: the orthographic line-scan's whole width for its half (1.7)
    borderline = shutil.copytree(borderline, tmp_path / "submission")
    camera = borderline / "raykit/linescan/camera.py"
    right = "origins = e + (camera.width / 2.0) * x[:, None] * u"
    assert camera.read_text().count(right) == 1
    camera.write_text(camera.read_text().replace(right, right.replace(" / 2.0", "")))

    def command(*arguments, cwd=assignment, env=home, python_option=False):
        start = [sys.executable] if python_option else [sys.executable, "-m", "raykit_grading"]
        run = subprocess.run([*start, *map(str, arguments)],
                             capture_output=True, text=True, cwd=cwd, env=env)  # fmt: skip
        assert run.returncode == 0, run.stderr[-3000:]
        return run

    released = command("release", "-o", "student-release/")
    visible = [t.name for t in TESTS if t.visibility == VISIBLE]
    shown = [f"release: {i} of {len(visible)}: {name}" for i, name in enumerate(visible, 1)]
    assert [li for li in released.stderr.splitlines() if li.startswith("release:")] == shown
    seed = read_seed_file(assignment / "grading-seed")
    said = f"raykit_grading: assignment seed {fingerprint(seed)}"
    assert f"{said} (./grading-seed, made now, mode 600" in released.stderr
    kit = [p for p in (assignment / "student-release").rglob("*") if p.is_file()]
    assert [p for p in kit if "seed" in p.name] == []
    assert not any(str(seed).encode() in p.read_bytes() for p in kit)

    zipped = command("gradescope", "-o", "autograder.zip")
    assert f"{said} (./grading-seed)\n" in zipped.stderr
    root = tmp_path / "autograder"  # laid out as Gradescope lays it out
    with zipfile.ZipFile(assignment / "autograder.zip") as opened:
        assert opened.read("grading-seed").decode().split()[-1] == str(seed)
        opened.extractall(root / "source")
    shutil.copy(root / "source/run_autograder", root / "run_autograder")
    shutil.copytree(borderline, root / "submission")
    on_gradescope = subprocess.run(
        ["bash", str(root / "run_autograder")],
        env={"PATH": "/usr/bin:/bin", "AUTOGRADER_ROOT": str(root),
             "RAYKIT_GRADER_PYTHON": grader_python,
             "RAYKIT_GRADE_OPTIONS": f"--only {' '.join(ONLY)}"},
        capture_output=True, text=True,
    )  # fmt: skip
    assert on_gradescope.returncode == 0, on_gradescope.stderr
    assert f"{said} (./grading-seed)\n" in on_gradescope.stderr  # run in source/

    (assignment / "graded").mkdir()
    graded = command("grade", borderline, "-o", "ada.json", "--only", *ONLY,
                     cwd=assignment / "graded")  # fmt: skip
    assert f"{said} ({assignment / 'grading-seed'})\n" in graded.stderr

    shutil.copytree(borderline, tmp_path / "class/ada")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    batch = command("batch", tmp_path / "class", "-o", assignment / "class",
                    "--only", *ONLY, "--assignment", assignment, cwd=elsewhere)  # fmt: skip
    assert f"{said} ({assignment / 'grading-seed'})\n" in batch.stderr
    assert list(elsewhere.iterdir()) == []

    ways = {
        "run_autograder": root / "results/results.json",
        "grade": assignment / "graded/ada.json",
        "batch": assignment / "class/feedback/ada/results.json",
    }
    results = {way: json.loads(path.read_text()) for way, path in ways.items()}
    scores = {way: {t["number"]: t["score"] for t in r["tests"]} for way, r in results.items()}
    assert list(scores["grade"]) == ONLY
    assert scores["run_autograder"] == scores["grade"] == scores["batch"], scores
    assert {r["extra_data"]["seed_fingerprint"] for r in results.values()} == {fingerprint(seed)}
    assert scores["grade"]["1.5"] > 0 and scores["grade"]["1.7"] == 0

    learn = command("prairielearn", "-o", "prairielearn/")
    assert f"{said} (./grading-seed)\n" in learn.stderr
    job = tmp_path / "grade"  # laid out as PrairieLearn lays out /grade
    shutil.copytree(assignment / "prairielearn/questions/raykit/tests", job / "tests")
    shutil.copytree(borderline / "raykit", job / "student/raykit")
    command("-c", "import sys; from raykit_grading.platforms.prairielearn import main; "
            "sys.exit(main())", "job", job, "--only", *ONLY, python_option=True)  # fmt: skip
    on_prairielearn = json.loads((job / "results/results.json").read_text())
    assert on_prairielearn["gradable"] and on_prairielearn["extra_data"][
        "seed_fingerprint"
    ] == fingerprint(seed)
    visible = {t["name"].split()[0]: t["points"] for t in on_prairielearn["tests"]
               if t["name"].split()[0] in ONLY}  # fmt: skip
    assert visible == {n: s for n, s in scores["grade"].items() if n in visible}
    total = sum(t["max_score"] for t in results["grade"]["tests"])
    assert on_prairielearn["score"] == round(results["grade"]["score"] / total, 6)

"""One secret seed per assignment: the same graded inputs on every grading, every machine.

A regrade must not change a grade: the graded inputs come from the assignment's seed file
(raykit_grading/seeds.py), the draw is the same on any processor and thread count, and
results.json names the seed by a fingerprint only."""

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
from raykit_grading.catalog import TESTS
from raykit_grading.grade import Options, grade
from raykit_grading.seeds import (
    SeedFileError,
    fingerprint,
    read_seed_file,
    seed_from_file,
)

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


DIGEST_IN_A_CHILD = f"""
import json
import sys

sys.path[:0] = {[str(REPO / "tests" / f) for f in ("grading", "support", "")] + [str(REPO)]!r}
from numpy._core import _multiarray_umath as umath
from test_grading_seeds import draw_digest

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
    tree = ast.parse((REPO / "raykit_grading/catalog.py").read_text())
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
def solution(tmp_path_factory):
    return make_submission(tmp_path_factory.mktemp("solution"))


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


def _grade_command(submission, results, *more):
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o", str(results),
         "--only", "1.5", "1.6", "1.7", *more],
        capture_output=True, text=True, cwd=REPO,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    return json.loads(results.read_text()), run


def test_a_borderline_submission_scores_the_same_when_graded_again(borderline, tmp_path):
    first, run = _grade_command(borderline, tmp_path / "graded/results.json")
    seed_file = tmp_path / "graded/grading-seed"
    assert f"made the grading seed {seed_file} (mode 600)" in run.stderr
    assert stat.S_IMODE(seed_file.stat().st_mode) == 0o600
    again, run = _grade_command(borderline, tmp_path / "graded/results.json")
    assert "made the grading seed" not in run.stderr
    scores = [(t["number"], t["score"]) for t in first["tests"]]
    assert scores == [(t["number"], t["score"]) for t in again["tests"]]
    assert first["score"] == again["score"]
    seed = read_seed_file(seed_file)
    assert first["extra_data"]["seed_fingerprint"] == fingerprint(seed)
    assert again["extra_data"]["seed_fingerprint"] == fingerprint(seed)
    assert str(seed) not in (tmp_path / "graded/results.json").read_text()
    # --seed overrides the file (and makes none), and repeats its own draw
    by_hand, _ = _grade_command(borderline, tmp_path / "r.json", "--seed", str(seed))
    assert [(t["number"], t["score"]) for t in by_hand["tests"]] == scores
    assert not (tmp_path / "grading-seed").exists()


def test_the_borderline_submission_is_borderline_its_score_depends_on_the_seed(
    borderline, child_python
):
    """Without one seed per assignment, its grade would change from run to run."""
    scores = {
        grade(borderline, names=["1.6"], seed=seed, options=Options(child_python))["score"]
        for seed in range(1, 9)
    }
    assert len(scores) > 1 and min(scores) < 2


def test_batch_grades_every_student_under_one_seed_and_regrades_under_another(
    tmp_path, child_python, borderline
):
    import shutil

    from raykit_grading.batch import grade_folder

    students = tmp_path / "submissions"
    for name in ("ada", "bob"):
        shutil.copytree(borderline, students / name)
    out = tmp_path / "out"
    options = Options(child_python)
    assert grade_folder(students, out, names=["1.6"], options=options) == 0
    seed = read_seed_file(out / "grading-seed")
    assert stat.S_IMODE((out / "grading-seed").stat().st_mode) == 0o600

    def graded():
        return {
            name: json.loads((out / "feedback" / name / "results.json").read_text())
            for name in ("ada", "bob")
        }

    first = graded()
    assert {r["extra_data"]["seed_fingerprint"] for r in first.values()} == {fingerprint(seed)}
    assert first["ada"]["score"] == first["bob"]["score"]  # the same code, the same tests
    before = {n: (out / "feedback" / n / "results.json").stat().st_mtime_ns for n in first}
    assert grade_folder(students, out, names=["1.6"], options=options) == 0
    after = {n: (out / "feedback" / n / "results.json").stat().st_mtime_ns for n in first}
    assert after == before  # graded under this seed already: not graded again
    assert grade_folder(students, out, names=["1.6"], options=options, seed=seed + 1) == 0
    regraded = graded()
    assert {r["extra_data"]["seed_fingerprint"] for r in regraded.values()} == {
        fingerprint(seed + 1)
    }


def test_the_zip_carries_the_seed_kept_beside_it_and_grades_under_it(tmp_path, grader_python):
    from raykit_grading.autograder import build_zip

    archive = build_zip(tmp_path / "autograder.zip")
    kept = tmp_path / "autograder.grading-seed"
    seed = read_seed_file(kept)
    assert stat.S_IMODE(kept.stat().st_mode) == 0o600
    rebuilt = build_zip(tmp_path / "again.zip", seed_file=kept)
    for path in (archive, rebuilt):
        with zipfile.ZipFile(path) as opened:
            inside = opened.read("grading-seed").decode()
            assert inside.split()[-1] == str(seed)
            assert opened.getinfo("grading-seed").external_attr >> 16 == 0o600
    root = tmp_path / "autograder"  # laid out as Gradescope lays it out
    with zipfile.ZipFile(archive) as opened:
        opened.extractall(root / "source")
    shutil.copy(root / "source/run_autograder", root / "run_autograder")
    make_submission(root / "submission")
    run = subprocess.run(
        ["bash", str(root / "run_autograder")],
        env={"PATH": "/usr/bin:/bin", "AUTOGRADER_ROOT": str(root),
             "RAYKIT_GRADER_PYTHON": grader_python, "RAYKIT_GRADE_OPTIONS": "--only 2.1"},
        capture_output=True, text=True,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    results = json.loads((root / "results/results.json").read_text())
    assert results["extra_data"]["seed_fingerprint"] == fingerprint(seed)
    assert results["score"] == 2

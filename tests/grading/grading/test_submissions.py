"""What students upload, in the shapes they get wrong: each graded end to end by ``grade``.

Students are asked for their ``raykit/`` folder, or a zip of it. A ``raykit/`` that is the only
one near the top (one or more folders too deep, in a zip, in a zip in a zip) is graded with a
one-line note saying where it was found; a shape the grader cannot take without guessing
(loose files, several raykit/ folders, no __init__.py, zips three deep) scores 0 with one line
saying what it found and what it expected, on every test and at the top of results.json."""

import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from conftest import REPO
from raykit_grading.grading.submissions import MAX_BYTES, SubmissionError, stage

EXPECTED = "expected raykit/__init__.py: upload your raykit/ folder itself, or a zip of it"
SOLUTION = sorted(
    p for p in (REPO / "raykit").rglob("*") if p.is_file() and "__pycache__" not in p.parts
)
TOP_MODULES = sorted(p.name for p in (REPO / "raykit").glob("*.py"))


def _copy(folder: Path) -> None:
    shutil.copytree(REPO / "raykit", folder, ignore=shutil.ignore_patterns("__pycache__"))


def _zip(path: Path, prefix: str = "", macos: bool = False) -> None:
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        for source in SOLUTION:
            name = f"{prefix}{source.relative_to(REPO)}"
            archive.write(source, name)
            if macos:  # what the Finder's "Compress" adds beside every file
                archive.writestr(f"__MACOSX/{Path(name).parent}/._{source.name}", b"\0\5\26\7")


def _zip_of(path: Path, inner: Path) -> None:
    with zipfile.ZipFile(path, "w") as archive:
        archive.write(inner, inner.name)
    inner.unlink()


def at_the_top(s):
    _copy(s / "raykit")


def one_folder_too_deep(s):
    _copy(s / "myname/raykit")


def the_whole_release_in_a_folder_with_a_build_copy(s):
    _copy(s / "student-release/raykit")
    _copy(s / "student-release/build/lib/raykit")  # what `pip install .` leaves: deeper
    (s / "student-release/README.md").write_text("# raykit: the starter kit\n")


def a_zip_of_it(s):
    _zip(s / "raykit.zip")


def a_zip_made_on_a_mac(s):
    _zip(s / "raykit.zip", macos=True)


def a_zip_of_the_folder_above_it(s):
    _zip(s / "homework.zip", prefix="myname/")


def a_zip_of_a_zip(s):
    _zip(s / "raykit.zip")
    _zip_of(s / "submission.zip", s / "raykit.zip")


def loose_files(s):
    for module in (REPO / "raykit").glob("*.py"):
        shutil.copy(module, s)


def loose_files_in_a_zip(s):
    with zipfile.ZipFile(s / "raykit.zip", "w") as archive:
        for module in (REPO / "raykit").glob("*.py"):
            archive.write(module, module.name)


def two_raykit_folders(s):
    _copy(s / "draft/raykit")
    _copy(s / "final/raykit")


def two_zips_each_with_raykit(s):
    _zip(s / "draft.zip")
    _zip(s / "final.zip")


def no_init(s):
    _copy(s / "raykit")
    (s / "raykit/__init__.py").unlink()


def a_zip_without_init(s):
    _zip(s / "raykit.zip")
    with zipfile.ZipFile(s / "raykit.zip") as archive, zipfile.ZipFile(s / "x.zip", "w") as out:
        for member in archive.infolist():
            if member.filename != "raykit/__init__.py":
                out.writestr(member, archive.read(member))
    (s / "raykit.zip").unlink()


def a_zip_of_a_zip_of_a_zip(s):
    _zip(s / "raykit.zip")
    _zip_of(s / "middle.zip", s / "raykit.zip")
    _zip_of(s / "outer.zip", s / "middle.zip")


def something_else(s):
    (s / "report.pdf").write_bytes(b"%PDF-1.4\n")
    (s / "notes.txt").write_text("see attached")


def nothing(s):
    pass


ACCEPTED = [
    (at_the_top, None),
    (one_folder_too_deep, "found myname/raykit/ (expected raykit/ at the top of the submission)"),
    (
        the_whole_release_in_a_folder_with_a_build_copy,
        "found student-release/raykit/ (expected raykit/ at the top of the submission)",
    ),
    (a_zip_of_it, None),
    (a_zip_made_on_a_mac, None),
    (
        a_zip_of_the_folder_above_it,
        "found myname/raykit/ in homework.zip (expected raykit/ at the top of the zip)",
    ),
    (
        a_zip_of_a_zip,
        "found raykit/ in raykit.zip inside submission.zip (a zip of a zip; expected the "
        "raykit/ folder or one zip of it)",
    ),
]

LOOSE = f"{', '.join(TOP_MODULES[:4])} and {len(TOP_MODULES) - 4} more"
REFUSED = [
    (
        loose_files,
        f"found loose Python files ({LOOSE}) instead of the raykit/ folder that holds them",
    ),
    (
        loose_files_in_a_zip,
        f"found loose Python files in raykit.zip ({LOOSE}) instead of the raykit/ folder that "
        "holds them",
    ),
    (no_init, "found raykit/ without an __init__.py"),
    (a_zip_without_init, "found raykit/ in x.zip without an __init__.py"),
    (
        a_zip_of_a_zip_of_a_zip,
        "found only zips inside zips (raykit.zip inside middle.zip inside outer.zip)",
    ),
    (something_else, "found no raykit/ folder, only notes.txt, report.pdf"),
    (nothing, "found an empty submission"),
]
SEVERAL = [
    (
        two_raykit_folders,
        "no raykit package: found 2 raykit/ folders (draft/raykit/, final/raykit/); expected "
        "one, at the top of the submission: upload your raykit/ folder itself, or a zip of it",
    ),
    (
        two_zips_each_with_raykit,
        "no raykit package: found raykit/ in 2 zips (draft.zip, final.zip); expected one: "
        "upload your raykit/ folder itself, or a zip of it",
    ),
]


def grade_shape(make, tmp_path: Path) -> dict:
    submission = tmp_path / "submission"
    submission.mkdir()
    make(submission)
    results = tmp_path / "results.json"
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o", str(results),
         "--only", "2.1", "2.3", "--seed", "31"],
        capture_output=True, text=True, cwd=REPO,
    )  # fmt: skip
    assert results.is_file(), run.stderr
    assert "Traceback" not in run.stderr
    return json.loads(results.read_text())


@pytest.mark.parametrize("make, note", ACCEPTED, ids=[m.__name__ for m, _ in ACCEPTED])
def test_a_raykit_folder_that_is_the_only_one_near_the_top_is_graded_and_located(
    make, note, tmp_path, child_python
):
    results = grade_shape(make, tmp_path)
    assert results["score"] == 4, results["tests"]
    notes = [line for line in results["output"].splitlines() if line.startswith("Note:")]
    assert notes == ([f"Note: {note}: graded it"] if note else [])


@pytest.mark.parametrize("make, found", REFUSED, ids=[m.__name__ for m, _ in REFUSED])
def test_a_submission_without_a_raykit_folder_is_told_what_was_found_and_expected(
    make, found, tmp_path, child_python
):
    results = grade_shape(make, tmp_path)
    message = f"no raykit package: {found}; {EXPECTED}"
    assert results["score"] == 0
    assert [t["output"] for t in results["tests"]] == [message, message]
    assert message in results["output"].splitlines()


@pytest.mark.parametrize("make, message", SEVERAL, ids=[m.__name__ for m, _ in SEVERAL])
def test_several_raykit_folders_are_not_guessed_between(make, message, tmp_path, child_python):
    results = grade_shape(make, tmp_path)
    assert results["score"] == 0
    assert [t["output"] for t in results["tests"]] == [message, message]
    assert message in results["output"].splitlines()


def test_the_zip_the_student_readme_says_to_make_is_graded_as_it_is(tmp_path, child_python):
    """The release README's command, run where it says (the folder holding raykit/), makes a
    zip the grader takes without a note."""
    from raykit_grading.assignment.release import STUDENT_README, ZIP_COMMAND

    readme = STUDENT_README.format(functions="", zip_command=ZIP_COMMAND)
    assert f"```bash\n{ZIP_COMMAND}\n```" in readme
    work = tmp_path / "student-release"
    _copy(work / "raykit")
    program, *arguments = ZIP_COMMAND.split()
    assert program == "python"
    subprocess.run([sys.executable, *arguments], cwd=work, check=True)

    def upload(s):
        shutil.copy(work / "raykit.zip", s)

    results = grade_shape(upload, tmp_path)
    assert results["score"] == 4, results["tests"]
    assert "Note:" not in results["output"]


def test_a_zip_in_a_zip_is_held_to_the_same_bounds_and_names(tmp_path):
    """The inner zip is unpacked by the same rules: no name leaves the folder, no bomb."""
    import io

    from raykit_grading.grading.submissions import MAX_BYTES, SubmissionError, stage

    inflating = {"raykit/__init__.py": b""}
    inflating |= {f"raykit/big{i}.py": b"\0" * (MAX_BYTES // 2) for i in range(3)}
    for name, members in {
        "escape": {"raykit/__init__.py": b"", "raykit/../../evil.py": b"x"},
        "bomb": inflating,
    }.items():
        inner = io.BytesIO()
        with zipfile.ZipFile(inner, "w", zipfile.ZIP_DEFLATED) as archive:
            for member, data in members.items():
                archive.writestr(member, data)
        source = tmp_path / name
        source.mkdir()
        with zipfile.ZipFile(source / "outer.zip", "w") as archive:
            archive.writestr("inner.zip", inner.getvalue())
        with pytest.raises(SubmissionError, match="^inner.zip inside outer.zip[: ]"):
            stage(source, tmp_path / f"{name}-staged")
    assert not list(tmp_path.rglob("evil.py"))


def test_staging_copies_plain_files_and_names_what_it_leaves_out(tmp_path):
    source = tmp_path / "submission"
    (source / "raykit" / "sub").mkdir(parents=True)
    (source / "raykit" / "__init__.py").write_text("")
    (source / "raykit" / "sub" / "x.py").write_text("X = 1\n")
    (source / "raykit" / "link.py").symlink_to("/etc/passwd")
    os.mkfifo(source / "raykit" / "pipe.py")
    staged = stage(source, tmp_path / "staged")
    assert staged.package == tmp_path / "staged" / "raykit"
    assert (staged.package / "sub" / "x.py").read_text() == "X = 1\n"
    assert not (staged.package / "link.py").exists()
    assert not (staged.package / "pipe.py").exists()
    assert staged.notes == [
        "raykit/link.py is a symbolic link: left out (only plain files count)",
        "raykit/pipe.py is a named pipe (FIFO): left out (only plain files count)",
    ]


def test_staging_refuses_a_zip_that_escapes_or_inflates(tmp_path):
    for name, members in {
        "escape": {"raykit/../../evil.py": b"x"},
        "bomb": {
            "raykit/__init__.py": b"",
            **{f"raykit/big{i}.py": b"\0" * (MAX_BYTES // 2) for i in range(3)},
        },
    }.items():
        source = tmp_path / name
        source.mkdir()
        with zipfile.ZipFile(source / "work.zip", "w", zipfile.ZIP_DEFLATED) as archive:
            for member, data in members.items():
                archive.writestr(member, data)
        with pytest.raises(SubmissionError):
            stage(source, tmp_path / f"{name}-staged")
    assert not (tmp_path / "evil.py").exists()

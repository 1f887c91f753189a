"""What a batch takes in (raykit_grading.grading.intake): every entry of a class is a student to
grade or a reason why not, whatever the class comes as: folders, zips, Gradescope's export
archive."""

from __future__ import annotations

import os
import zipfile

from gradescope_export import ASSIGNMENT, METADATA, make_export

from raykit_grading.grading.intake import entries, read_metadata


def _student(folder):
    (folder / "raykit").mkdir(parents=True)
    (folder / "raykit/__init__.py").write_text("")
    return folder


def _zipped(path):
    """A student's zip of ``raykit/`` (an empty package), as uploaded."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("raykit/__init__.py", "")
    return path


def _found(submissions, scratch):
    return {e.name: (e.folder is not None, e.why) for e in entries(submissions, scratch)}


def test_the_exports_yaml_gives_each_submission_folder_its_submitters_names():
    assert read_metadata(METADATA) == {
        "submission_241730101": ["Grace Hopper"],
        "submission_241730202": ["Alan Turing", "Kathleen O'Brien"],
    }


def test_the_exports_yaml_reads_no_names_from_the_history_and_falls_back_to_the_sid():
    text = (
        "submission_1:\n  :submitters:\n  - :sid: '42'\n    :email: x@example.edu\n"
        "  :history:\n  - :id: 7\n    :submitters:\n    - :name: Someone Else\n"
        'submission_2:\n  :submitters:\n  - :name: "Bj\\u00f8rn"\n'
    )
    assert read_metadata(text) == {"submission_1": ["42"], "submission_2": ["Bjørn"]}


def test_a_folder_of_folders_zips_and_other_files_lists_every_entry(tmp_path):
    students = tmp_path / "class"
    _student(students / "ada")
    _zipped(students / "erin.zip")
    (students / "notes.txt").write_text("to do")
    os.symlink("/etc", students / "link")
    found = _found(students, tmp_path / "scratch")
    assert found == {
        "ada": (True, ""),
        "erin": (True, ""),
        "link": (False, "a symbolic link: not followed"),
        "notes.txt": (False, "not a folder or a zip"),
    }
    erins = next(e for e in entries(students, tmp_path / "again") if e.name == "erin")
    assert sorted(p.name for p in erins.folder.iterdir()) == ["erin.zip"]  # staged as uploaded


def test_a_gradescope_export_zip_is_one_student_per_submission_named_from_its_yaml(tmp_path):
    (tmp_path / "class").mkdir()
    export = make_export(
        tmp_path / "class/submissions.zip",
        {
            "submission_241730101": _student(tmp_path / "grace"),
            "submission_241730202": _student(tmp_path / "pair"),
        },
    )
    for given in (export, tmp_path / "class"):  # the archive itself, or a folder holding it
        found = {e.name: e for e in entries(given, tmp_path / f"scratch-{given.name}")}
        assert set(found) == {"Grace Hopper", "Alan Turing & Kathleen O'Brien"}
        assert found["Grace Hopper"].folder.name == "submission_241730101"
        assert (found["Grace Hopper"].folder / "raykit/__init__.py").is_file()


def test_an_unzipped_export_whose_yaml_names_a_missing_folder_says_so(tmp_path):
    export = tmp_path / ASSIGNMENT
    export.mkdir()
    (export / "submission_metadata.yml").write_text(METADATA)
    _student(export / "submission_241730101")
    _student(export / "submission_99")  # not in the YAML: graded under its folder's name
    assert _found(export, tmp_path / "scratch") == {
        "Grace Hopper": (True, ""),
        "Alan Turing & Kathleen O'Brien": (
            False,
            "submission_metadata.yml names submission_241730202, which is not in the export",
        ),
        "submission_99": (True, ""),
    }


def test_an_export_member_that_leaves_its_folder_refuses_that_submission_only(tmp_path):
    path = tmp_path / "export.zip"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr(f"{ASSIGNMENT}/submission_metadata.yml", METADATA)
        archive.writestr(f"{ASSIGNMENT}/submission_241730101/raykit/__init__.py", "")
        archive.writestr(f"{ASSIGNMENT}/submission_241730202/../../escaped.py", "x = 1")
        archive.writestr(f"{ASSIGNMENT}/submission_241730202/raykit/__init__.py", "")
    found = _found(path, tmp_path / "scratch")
    assert found["Grace Hopper"] == (True, "")
    graded, why = found["Alan Turing & Kathleen O'Brien"]
    assert not graded and why.startswith("in export.zip: a file name that leaves its folder")
    assert not list(tmp_path.rglob("escaped.py"))


def test_names_are_unique_and_fit_a_folder(tmp_path):
    students = tmp_path / "class"
    _student(students / "erin")
    _zipped(students / "erin.zip")
    assert sorted(_found(students, tmp_path / "scratch")) == ["erin", "erin (2)"]


def test_a_zip_of_a_class_folder_is_read_as_the_folder(tmp_path):
    path = tmp_path / "class.zip"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("ada/raykit/__init__.py", "")
        archive.write(_zipped(tmp_path / "erin.zip"), "erin.zip")
        archive.writestr("notes.txt", "to do")
    assert _found(path, tmp_path / "scratch") == {
        "ada": (True, ""),
        "erin": (True, ""),
        "notes.txt": (False, "not a folder or a zip"),
    }

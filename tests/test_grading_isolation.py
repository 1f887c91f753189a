"""The grader's machinery around the sandbox: uid leases, workspaces, staging, what ships."""

from __future__ import annotations

import fcntl
import os
import time
import zipfile

import pytest
import tomllib

from conftest import REPO
from raykit_grading.isolation import UidPool
from raykit_grading.submissions import MAX_BYTES, SubmissionError, stage
from raykit_grading.workspace import PREFIX, Workspace, clean_stale

AS_ROOT = os.geteuid() == 0


@pytest.mark.skipif(not AS_ROOT, reason="sandbox uids are leased only when grading as root")
def test_two_graders_never_lease_the_same_uid(tmp_path):
    locks = tmp_path / "uids"
    first, second = UidPool(range(61000, 61003), locks), UidPool(range(61000, 61003), locks)
    leases = [first.lease(), second.lease(), first.lease()]
    assert len({lease.uid for lease in leases}) == 3
    with pytest.raises(RuntimeError, match="all 3 sandbox uids are in use"):
        second.lease()
    leases[1].release()
    assert second.lease().uid == leases[1].uid


def test_a_killed_graders_workspace_is_removed_by_the_next_one(tmp_path):
    stale = tmp_path / f"{PREFIX}stale"
    stale.mkdir()
    (stale / ".lock").write_text("")
    (stale / "task-1").mkdir()
    busy = tmp_path / f"{PREFIX}busy"
    busy.mkdir()
    held = os.open(busy / ".lock", os.O_RDWR | os.O_CREAT)
    fcntl.flock(held, fcntl.LOCK_EX)  # a grader still running
    unlocked_old = tmp_path / f"{PREFIX}never-locked"
    unlocked_old.mkdir()
    os.utime(unlocked_old, (time.time() - 3600, time.time() - 3600))
    try:
        with Workspace(tmp_path) as mine:
            assert mine.is_dir() and (mine / ".lock").is_file()
            assert clean_stale(tmp_path) == []  # its own is locked
        assert not stale.exists() and not unlocked_old.exists() and busy.exists()
        assert not mine.exists()
    finally:
        os.close(held)


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


def test_the_wheel_holds_raykit_and_its_grader_but_no_hidden_scenes():
    from setuptools import find_packages

    config = tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages = find_packages(str(REPO), include=config["packages"]["find"]["include"])
    assert "grading" not in packages and "raykit_grading" in packages
    assert {p.split(".")[0] for p in packages} == {"raykit", "raykit_grading"}
    data = config.get("package-data", {})
    assert all("scenes" not in pattern for patterns in data.values() for pattern in patterns)
    assert not list((REPO / "raykit_grading").rglob("*.json"))


def test_the_grader_says_plainly_when_it_has_no_clone_to_read_scenes_from(monkeypatch, tmp_path):
    import raykit_grading.grade as grade

    monkeypatch.setattr(grade, "HIDDEN_SCENES", tmp_path / "nowhere")
    with pytest.raises(grade.GradingImpossible, match="needs a clone of the course repository"):
        grade.check_clone()


def test_setup_sh_pins_the_versions_the_references_are_made_with(tmp_path):
    import numpy
    import PIL

    from raykit_grading.gradescope import build_zip

    with zipfile.ZipFile(build_zip(tmp_path / "ag.zip")) as archive:
        setup = archive.read("setup.sh").decode()
        names = archive.namelist()
    assert f"numpy=={numpy.__version__}" in setup and f"Pillow=={PIL.__version__}" in setup
    assert "bubblewrap" in setup
    assert "source/grading-scenes/odd.json" in names
    assert not any("__pycache__" in name for name in names)

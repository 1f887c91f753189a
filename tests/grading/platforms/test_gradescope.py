"""The Gradescope autograder zip (raykit_grading.platforms.gradescope): at its top, what
Gradescope puts in /autograder/source."""

from __future__ import annotations

import zipfile


def test_the_zip_holds_at_its_top_what_gradescope_puts_in_autograder_source(tmp_path):
    """Gradescope extracts the zip into /autograder/source: setup.sh, run_autograder, the
    requirements, the seed and the grader's packages are at the zip's top, not in a folder."""
    from raykit_grading.platforms.gradescope import REQUIREMENTS, build_zip

    with zipfile.ZipFile(build_zip(tmp_path / "ag.zip")) as archive:
        setup = archive.read("setup.sh").decode()
        names = archive.namelist()
        pinned = archive.read("grader-requirements.txt")
    tops = {name.split("/", 1)[0] for name in names}
    assert tops == {"setup.sh", "run_autograder", "grader-requirements.txt", "grading-seed",
                    "raykit", "raykit_grading", "scenes", "grading"}  # fmt: skip
    assert "raykit_grading/__main__.py" in names and "grading/hidden-scenes/odd.json" in names
    assert pinned == REQUIREMENTS.read_bytes()
    assert '-r "$source/grader-requirements.txt"' in setup and "bubblewrap" in setup
    assert not any("__pycache__" in name for name in names)

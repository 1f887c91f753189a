"""The Gradescope autograder zip.

    python -m raykit_grading gradescope -o autograder.zip

Gradescope extracts the zip into ``/autograder/source``, copies ``run_autograder`` from there to
``/autograder/run_autograder``, and runs ``setup.sh`` once, as root, when it builds the image.
So the zip's top holds exactly what ``/autograder/source`` is to hold: ``setup.sh``,
``run_autograder``, ``grader-requirements.txt``, ``grading-seed`` (a copy of the assignment's
secret seed, :mod:`raykit_grading.assignment.seeds`: every submission and every regrade is graded on
the inputs drawn from it, as ``grade`` and ``batch`` grade in the assignment folder), the grader,
the reference raykit, the scenes and the hidden scenes.

* ``setup.sh`` installs bubblewrap (the sandbox, :mod:`raykit_grading.sandbox.isolation`), and a
  Python (``/opt/raykit-grader``) with what ``grader-requirements.txt`` pins and nothing else: the
  references are computed with it at grading time, and submissions run on the same interpreter,
  inside the sandbox, which shows them numpy and Pillow only. The pins are the repository's,
  not the builder's: each has wheels for the Python of every base image Gradescope offers.
  It builds the chroot sandbox's tree (:mod:`raykit_grading.sandbox.confine`), used where Docker's
  default confinement refuses bubblewrap its namespaces (as on Gradescope), and closes
  ``/autograder/source`` to everyone but root.
* ``run_autograder`` grades ``/autograder/submission`` (a folder or a zip in it) under the
  seed in ``source/grading-seed`` and writes ``/autograder/results/results.json``; it exits 0
  when it graded, whatever the score (a submission with nothing to grade scores 0 and says
  why), and non-zero only if the grader could not grade (results.json then says NOT GRADED on
  every test).

Set Gradescope's autograder timeout to at least 12 minutes: one submission's tests may take
480 s together (``--total-seconds``), plus the reference renders and start-up.

``AUTOGRADER_ROOT`` and ``RAYKIT_GRADER_PYTHON`` change the paths, so the same script runs in a
test on any machine.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

from raykit_grading.assignment.catalog import REPO
from raykit_grading.assignment.seeds import HEADER, new_seed

SETUP = """#!/usr/bin/env bash
# Gradescope runs this once, as root, in /autograder/source (this zip's contents), when it
# builds the autograder's image.
set -euo pipefail
source=$(cd "$(dirname "${{BASH_SOURCE[0]}}")" && pwd)
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq python3 python3-venv bubblewrap
python3 -m venv /opt/raykit-grader
/opt/raykit-grader/bin/pip install -q --disable-pip-version-check \\
  -r "$source/{requirements}"
chmod -R a+rX /opt/raykit-grader
# the chroot sandbox's tree, made now so that no grading pays for it
PYTHONPATH="$source" /opt/raykit-grader/bin/python -m raykit_grading.sandbox.confine
# submissions run in a sandbox, as an unprivileged uid (50000-59999): none of this is in it
chmod 700 "$source"
# the assignment's secret seed, root's alone (PrairieLearn's image has none: the seed comes
# with each grading job, from the question's tests/ folder)
if [ -e "$source/grading-seed" ]; then chmod 600 "$source/grading-seed"; fi
"""

RUN = """#!/usr/bin/env bash
# Gradescope runs this, as root, for every submission.
set -uo pipefail
root="${{AUTOGRADER_ROOT:-/autograder}}"
grader_python="${{RAYKIT_GRADER_PYTHON:-/opt/raykit-grader/bin/python}}"
results="$root/results/results.json"
mkdir -p "$root/results"
rm -f "$results"
cd "$root/source" || exit 3
# RAYKIT_GRADE_OPTIONS (e.g. "--only 3.6 --wall-seconds 5") is for testing this script
# shellcheck disable=SC2086
PYTHONPATH="$root/source" "$grader_python" -m raykit_grading grade "$root/submission" \\
  -o "$results" --seed-file "$root/source/grading-seed" ${{RAYKIT_GRADE_OPTIONS:-}}
status=$?
if [ ! -s "$results" ]; then  # the grader did not run at all: say so, never a silent zero
  echo "raykit_grading: error: the grader could not run (exit status $status)" >&2
  printf '%s\\n' '{{"score": 0, "visibility": "visible", "tests": [], "output":' \\
    '"NOT GRADED: the autograder could not run here; ask your instructor"}}' > "$results"
  exit 3
fi
exit "$status"
"""


REQUIREMENTS = Path(__file__).parents[1] / "grader-requirements.txt"
GRADER_FOLDERS = ("raykit", "raykit_grading", "scenes")  # what every grader image holds
HIDDEN_FOLDER = "grading/hidden-scenes"  # secret: in Gradescope's zip, never in a public image


def setup_script() -> str:
    """setup.sh: what builds a grader image (Gradescope's and PrairieLearn's alike)."""
    return SETUP.format(requirements=REQUIREMENTS.name)


def grader_files(folders: tuple[str, ...] = GRADER_FOLDERS):
    """(name in the grader's source folder, file in this repository) of the grader, the
    reference raykit and the scenes, and the pinned requirements."""
    yield REQUIREMENTS.name, REQUIREMENTS
    for folder in folders:
        for path in sorted((REPO / folder).rglob("*")):
            if path.is_file() and "__pycache__" not in path.parts:
                yield str(path.relative_to(REPO)), path


def build_zip(out: Path, seed: int | None = None) -> Path:
    """Write the autograder zip to ``out``, grading under ``seed``: the assignment's (the
    command passes :func:`raykit_grading.assignment.seeds.assignment_seed`'s); None draws one that
    only this zip holds."""
    out = Path(out)
    seed = new_seed() if seed is None else seed
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        scripts = (("setup.sh", setup_script()), ("run_autograder", RUN.format()))
        for name, text in scripts:
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o755 << 16
            archive.writestr(info, text)
        info = zipfile.ZipInfo("grading-seed")
        info.external_attr = 0o600 << 16  # and setup.sh closes source/ to root
        archive.writestr(info, f"{HEADER}{seed}\n")
        for name, path in grader_files((*GRADER_FOLDERS, HIDDEN_FOLDER)):
            archive.write(path, name)
    print(f"wrote {out}: upload it to Gradescope")
    return out

"""The Gradescope autograder zip.

    python -m raykit_grading gradescope -o autograder.zip

The zip holds ``setup.sh`` and ``run_autograder`` at its top, and ``source/`` with the grader,
the reference raykit, the scenes, the hidden scenes and ``grading-seed``, the assignment's
secret seed (:mod:`raykit_grading.seeds`): every submission and every regrade is graded on the
inputs drawn from it. The builder keeps it beside the zip (``autograder.grading-seed``, mode
600; or ``--seed-file``), so a zip built again grades the same inputs. On Gradescope's Ubuntu
image:

* ``setup.sh`` installs bubblewrap (the sandbox, :mod:`raykit_grading.isolation`) and a Python
  with numpy and Pillow pinned to the versions of the machine that built the zip (the
  references are computed with them at grading time, and submissions run on the same
  interpreter, inside the sandbox, which shows them numpy and Pillow only); and it closes
  ``/autograder/source`` to everyone but root.
  It also builds the chroot sandbox's tree (:mod:`raykit_grading.confine`), used where
  Docker's default confinement refuses bubblewrap its namespaces (as on Gradescope).
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

from raykit_grading.catalog import REPO
from raykit_grading.seeds import HEADER, fingerprint, seed_from_file

SETUP = """#!/usr/bin/env bash
# Gradescope runs this once, as root, when the autograder is built.
set -euo pipefail
apt-get update -qq
apt-get install -y -qq python3 python3-pip python3-venv bubblewrap
python3 -m venv /opt/raykit-grader
/opt/raykit-grader/bin/pip install -q {pins} tqdm
chmod -R a+rX /opt/raykit-grader
# the chroot sandbox's tree, made now so that no grading pays for it
PYTHONPATH=/autograder/source /opt/raykit-grader/bin/python -m raykit_grading.confine
# submissions run in a sandbox, as an unprivileged uid (50000-59999): none of this is in it
chmod 700 /autograder/source
chmod 600 /autograder/source/grading-seed  # the assignment's secret seed: root's alone
"""

RUN = """#!/usr/bin/env bash
# Gradescope runs this, as root, for every submission.
set -uo pipefail
root="${{AUTOGRADER_ROOT:-/autograder}}"
grader_python="${{RAYKIT_GRADER_PYTHON:-/opt/raykit-grader/bin/python}}"
[ -x "$grader_python" ] || grader_python=python3
mkdir -p "$root/results"
cd "$root/source" || exit 3
# RAYKIT_GRADE_OPTIONS (e.g. "--only 3.6 --wall-seconds 5") is for testing this script
# shellcheck disable=SC2086
PYTHONPATH="$root/source" exec "$grader_python" -m raykit_grading grade "$root/submission" \\
  -o "$root/results/results.json" --seed-file "$root/source/grading-seed" \\
  ${{RAYKIT_GRADE_OPTIONS:-}}
"""


def pins() -> str:
    """numpy and Pillow at the versions this machine has (the references' own)."""
    import numpy
    import PIL

    return f"numpy=={numpy.__version__} Pillow=={PIL.__version__}"


def build_zip(out: Path, seed_file: Path | None = None) -> Path:
    """Write the autograder zip to ``out``, with the seed in ``seed_file`` (made if missing;
    default ``autograder.grading-seed`` beside the zip)."""
    out = Path(out)
    seed_file = Path(seed_file or out.with_suffix(".grading-seed"))
    seed, made = seed_from_file(seed_file)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        scripts = (("setup.sh", SETUP.format(pins=pins())), ("run_autograder", RUN.format()))
        for name, text in scripts:
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o755 << 16
            archive.writestr(info, text)
        info = zipfile.ZipInfo("source/grading-seed")
        info.external_attr = 0o600 << 16  # and setup.sh closes source/ to root
        archive.writestr(info, f"{HEADER}{seed}\n")
        for folder in ("raykit", "raykit_grading", "scenes", "grading/hidden-scenes"):
            for path in sorted((REPO / folder).rglob("*")):
                if path.is_file() and "__pycache__" not in path.parts:
                    archive.write(path, f"source/{path.relative_to(REPO)}")
    kept = "made now" if made else "kept"
    print(f"wrote {out}: grading seed {fingerprint(seed)} from {seed_file} ({kept}: build "
          "the zip again with it for the same graded inputs)")  # fmt: skip
    return out

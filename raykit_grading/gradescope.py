"""The Gradescope autograder zip.

    python -m raykit_grading gradescope -o autograder.zip

The zip holds ``setup.sh`` and ``run_autograder`` at its top, and ``source/`` with the grader,
the reference raykit, the scenes and the hidden scenes. On Gradescope's Ubuntu image:

* ``setup.sh`` installs Python with numpy and Pillow for the grader, and a separate virtual
  environment (numpy and Pillow only, readable by all) that submissions run in, as an
  unprivileged uid; and it closes ``/autograder/source`` to everyone but root.
* ``run_autograder`` grades ``/autograder/submission`` and writes
  ``/autograder/results/results.json`` (the grader writes it in every case).

``AUTOGRADER_ROOT``, ``RAYKIT_GRADER_PYTHON`` and ``RAYKIT_CHILD_PYTHON`` change the paths, so
the same script runs in a test on any machine.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

from raykit_grading.catalog import REPO

SETUP = """#!/usr/bin/env bash
# Gradescope runs this once, as root, when the autograder is built.
set -euo pipefail
apt-get update -qq
apt-get install -y -qq python3 python3-pip python3-venv
python3 -m venv /opt/raykit-grader
/opt/raykit-grader/bin/pip install -q numpy Pillow tqdm
# the submissions' own Python: numpy and Pillow, no raykit, runnable by the sandbox user
python3 -m venv /opt/raykit-sandbox
/opt/raykit-sandbox/bin/pip install -q numpy Pillow
chmod -R a+rX /opt/raykit-sandbox
# submissions run as an unprivileged uid (50000-59999) that can read none of this
chmod 700 /autograder/source
"""

RUN = """#!/usr/bin/env bash
# Gradescope runs this, as root, for every submission.
set -uo pipefail
root="${AUTOGRADER_ROOT:-/autograder}"
grader_python="${RAYKIT_GRADER_PYTHON:-/opt/raykit-grader/bin/python}"
[ -x "$grader_python" ] || grader_python=python3
child_python="${RAYKIT_CHILD_PYTHON:-/opt/raykit-sandbox/bin/python}"
mkdir -p "$root/results"
cd "$root/source" || exit 1
submission="$root/submission"
# a submitted zip is unpacked first
for archive in "$submission"/*.zip; do
  [ -e "$archive" ] && "$grader_python" -m zipfile -e "$archive" "$submission/" || true
done
# RAYKIT_GRADE_OPTIONS (e.g. "--only 3.6 --wall-seconds 5") is for testing this script
# shellcheck disable=SC2086
PYTHONPATH="$root/source" "$grader_python" -m raykit_grading grade "$submission" \\
  -o "$root/results/results.json" --child-python "$child_python" ${RAYKIT_GRADE_OPTIONS:-}
"""


def build_zip(out: Path) -> Path:
    """Write the autograder zip to ``out``."""
    out = Path(out)
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, text in (("setup.sh", SETUP), ("run_autograder", RUN)):
            info = zipfile.ZipInfo(name)
            info.external_attr = 0o755 << 16
            archive.writestr(info, text)
        for folder in ("raykit", "raykit_grading", "scenes", "grading-scenes"):
            for path in sorted((REPO / folder).rglob("*")):
                if path.is_file() and "__pycache__" not in path.parts:
                    archive.write(path, f"source/{path.relative_to(REPO)}")
    print(f"wrote {out}")
    return out

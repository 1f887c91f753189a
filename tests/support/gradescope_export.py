"""A small Gradescope "Export Submissions" archive, shaped as the download is.

The layout, as tools that read these archives find it (otter-grader's ``GradescopeParser``, which
reads ``submission_metadata.yml`` from the export's folder and each top-level key's
``:submitters`` ``:name``; scripts that rename each ``submission_<id>`` folder by its first
submitter's ``:sid``; scripts that read ``:created_at``, ``:score`` and ``:history``; a tool's
test that builds an export as ``assignment_<id>_export/submission_metadata.yml`` beside
``assignment_<id>_export/submission_<id>/``): one folder ``assignment_<id>_export/`` holding
the YAML, written by Ruby (symbol keys with a leading colon), and one folder per submission
holding the files as the student uploaded them. A group submission lists several submitters.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

ASSIGNMENT = "assignment_5551234_export"

METADATA = """---
submission_241730101:
  :submitters:
  - :name: Grace Hopper
    :sid: '1001'
    :email: grace@example.edu
  :created_at: 2026-03-01 12:34:56.789012000 -08:00
  :score: 31.0
  :history:
  - :id: 241729900
    :created_at: 2026-02-28 22:10:03.000000000 -08:00
    :score: 12.0
submission_241730202:
  :submitters:
  - :name: Alan Turing
    :sid: '1002'
    :email: alan@example.edu
  - :name: 'Kathleen O''Brien'
    :sid: '1003'
    :email: kathleen@example.edu
  :created_at: 2026-03-01 23:59:01.000000000 -08:00
  :score: 0.0
  :history: []
"""


def make_export(path: Path, submissions: dict[str, Path]) -> Path:
    """Write the export zip at ``path``: ``submissions`` maps each submission folder's name
    (``submission_241730101``, ...) to a folder whose files it holds."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr(f"{ASSIGNMENT}/submission_metadata.yml", METADATA)
        for name, folder in submissions.items():
            for file in sorted(folder.rglob("*")):
                if file.is_file() and "__pycache__" not in file.parts:
                    relative = file.relative_to(folder).as_posix()
                    archive.write(file, f"{ASSIGNMENT}/{name}/{relative}")
    return path

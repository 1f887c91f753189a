"""Make the pictures in README.md and docs/ with raykit's own commands.

    python docs/make_images.py [OUT_FOLDER]

runs each command below (the same ones README shows) and writes into OUT_FOLDER (default:
docs/images). The tests run it into a temporary folder and compare with the committed images.
"""

from __future__ import annotations

import sys
from pathlib import Path

from raykit.cli import main

REPO = Path(__file__).resolve().parent.parent

# (output name, the raykit command line that makes it, with {out} for the output path)
IMAGES = [
    ("classic.png", "render scenes/classic.json -o {out}"),
    ("cutouts.png", "render scenes/cutouts.json -o {out} --samples 3"),
]


def make(folder: Path, names: list[str] | None = None) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for name, command in IMAGES:
        if names and name not in names:
            continue
        args = command.format(out=folder / name).split()
        args[1] = str(REPO / args[1])  # the scene, wherever this is run from
        if main(args) != 0:
            raise SystemExit(f"failed: raykit {command}")


if __name__ == "__main__":
    make(Path(sys.argv[1]) if len(sys.argv) > 1 else REPO / "docs" / "images")

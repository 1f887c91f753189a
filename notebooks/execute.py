"""Run every notebook top to bottom and store its outputs (what nbval then checks).

    python notebooks/execute.py [NOTEBOOK.ipynb ...]

Run it after changing raykit or a notebook, and commit the notebooks it rewrote. It prints one
line per notebook as it is stored (its name and time); on a terminal, a bar of the cells run
appears while a notebook takes more than a second.

It needs ipywidgets (``pip install -e ".[notebooks]"``): without it the slider cells would store
no widget outputs, and the notebooks would lose their sliders; it refuses instead (exit 2).
"""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence
from pathlib import Path

from raykit.io.progress import progress_bar

HERE = Path(__file__).resolve().parent

NEEDS = 'pip install -e ".[notebooks]"'


def execute(path: Path) -> float:
    """Run the notebook at ``path`` and store it with its new outputs; returns the seconds."""
    import nbformat
    from nbclient import NotebookClient

    notebook = nbformat.read(path, as_version=4)
    start = time.perf_counter()
    with progress_bar(len(notebook.cells), path.name, "cell") as advance:
        NotebookClient(
            notebook,
            timeout=300,
            kernel_name="python3",
            record_timing=False,  # no per-cell timestamps: a rerun changes only what its outputs do
            resources={"metadata": {"path": str(path.parent)}},
            on_cell_executed=None if advance is None else lambda **_: advance(1),
        ).execute()
    nbformat.write(notebook, path)
    return time.perf_counter() - start


def main(argv: Sequence[str] | None = None) -> int:
    try:
        import ipywidgets  # noqa: F401
    except ImportError:
        print(
            "notebooks/execute.py: error: ipywidgets is not installed, and without it the "
            f"notebooks' sliders would be stored empty; install it with {NEEDS}",
            file=sys.stderr,
        )
        return 2
    names = sys.argv[1:] if argv is None else argv
    paths = [Path(p) for p in names] or sorted(HERE.glob("*.ipynb"))
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        print(f"notebooks/execute.py: error: {missing[0]}: no such notebook", file=sys.stderr)
        return 2
    for path in paths:
        print(f"{path.name}: {execute(path):.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

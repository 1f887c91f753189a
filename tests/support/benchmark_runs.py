"""Running a benchmark script as its tests do: ``--quick``, its tables read back, or its module
imported (tests/test_benchmarks.py, and tests/compiled/test_benchmarks.py for those that need
the compiled engine)."""

import importlib
import subprocess
import sys
from types import ModuleType

from conftest import REPO

# a benchmark's process may first compile the compiled engine's kernels (raykit[fast] installed,
# nothing of this source cached; how long: docs/benchmarks/compile_time.md), then load them
TIMEOUT = 1200


def tables(script: str, *extra: str, repeats: bool = True) -> list[list[str]]:
    """The lines of each block (blank-line separated) ``script --quick`` prints, with
    ``--repeats 1`` unless ``repeats`` is false (a benchmark that times nothing takes no
    --repeats); the script must succeed."""
    once = ["--repeats", "1"] if repeats else []
    run = subprocess.run(
        [sys.executable, str(REPO / "benchmarks" / script), "--quick", *once, *extra],
        capture_output=True,
        text=True,
        timeout=TIMEOUT,
    )
    assert run.returncode == 0, run.stderr
    return [t.splitlines() for t in run.stdout.split("\n\n")]


def table_rows(script: str, *extra: str, repeats: bool = True) -> list[str]:
    """The rows of the first table :func:`tables` finds."""
    first = next(t for t in tables(script, *extra, repeats=repeats) if t and t[0].startswith("| "))
    return [line for line in first if line.startswith("| ")][1:]  # the first table's rows


def benchmark_module(name: str) -> ModuleType:
    """The benchmark script ``benchmarks/<name>.py`` imported as a module."""
    if str(REPO / "benchmarks") not in sys.path:
        sys.path.insert(0, str(REPO / "benchmarks"))
    return importlib.import_module(name)

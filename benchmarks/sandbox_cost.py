"""What the grader's sandbox costs: one task's child with and without bubblewrap around it.

    python benchmarks/sandbox_cost.py [--runs N]

Times, side by side in one run (interleaved, medians):

* ``bare``: the child's interpreter importing numpy and Pillow, as a plain process;
* ``sandboxed``: the same command inside the sandbox the grader builds for a task
  (:func:`raykit_grading.isolation.sandbox_arguments`: mount, pid, network, ipc, uts
  namespaces; as root also the switch to a task uid happens in the child, not timed here);
* ``task``: a whole :meth:`raykit_grading.sandbox.Sandbox.run` of the preflight task (work
  folder, inputs, sandbox, results over the pipe, clean-up), as each graded test pays it.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from raykit_grading.isolation import find_bwrap, probe_python, sandbox_arguments  # noqa: E402
from raykit_grading.sandbox import Sandbox  # noqa: E402
from raykit_grading.workspace import Workspace  # noqa: E402

IMPORTS = "import sys; sys.path.insert(0, '{site}'); import numpy, PIL.Image"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, allow_abbrev=False)
    parser.add_argument("--runs", type=int, default=15)
    runs = parser.parse_args().runs
    python = probe_python(sys.executable)
    bwrap = find_bwrap()
    import os

    as_root = os.geteuid() == 0
    times: dict[str, list[float]] = {"bare": [], "sandboxed": [], "task": []}
    with Workspace() as workspace:
        empty = workspace / "empty"
        empty.mkdir(mode=0o755)
        sandbox = Sandbox(empty, workspace)
        work = Path(tempfile.mkdtemp(dir=workspace))
        (work / "submission").mkdir()
        work.chmod(0o755)
        site = str(Path(python.packages[0]).parent)
        bare = [python.executable, "-I", "-S", "-c", IMPORTS.format(site=site)]
        arguments = sandbox_arguments(python, work, empty, 2**20, as_root)
        boxed = [bwrap, *arguments, python.executable, "-I", "-S", "-c",
                 IMPORTS.format(site="/sandbox/site")]  # fmt: skip
        for _ in range(runs):
            for name, run in (
                ("bare", lambda: subprocess.run(bare, check=True)),
                ("sandboxed", lambda: subprocess.run(boxed, check=True)),
                ("task", lambda: sandbox.run("probe", {}, {})),
            ):
                start = time.perf_counter()
                run()
                times[name].append(time.perf_counter() - start)
    bare_median = statistics.median(times["bare"])
    print(f"one task's child, {runs} runs each, interleaved (as {'root' if as_root else 'user'})")
    print(f"{'':<10} {'median':>9} {'min':>9} {'max':>9} {'/ bare':>7}")
    for name, values in times.items():
        median = statistics.median(values)
        print(
            f"{name:<10} {median * 1000:>7.1f}ms {min(values) * 1000:>7.1f}ms "
            f"{max(values) * 1000:>7.1f}ms {median / bare_median:>7.2f}"
        )


if __name__ == "__main__":
    main()

"""How long grading takes, and how much memory, in a container like Gradescope's default one.

    python benchmarks/grading_in_a_container.py [--memory-mb 768] [--cpus 0.5] [--quick]
        [--page docs/benchmarks/grading_in_a_container.md]

As root: ``python -m raykit_grading grade`` under ``tests/support/docker_confinement.py`` (Docker's
default capabilities and seccomp rules, a cgroup v1 memory limit and CPU quota of its own), on

* the full solution, and
* the worst case for time: every test's code hangs until it is stopped (``time.sleep`` at
  import), so the grading takes the 480 s all of a submission's tests may take together;

and says the score, the sandbox used, the whole grading's wall time and the container's peak
memory (its cgroup's ``memory.max_usage_in_bytes``, page cache included). ``--quick`` grades
only the full solution. The table is printed and written to ``--page`` (by default, but not
with ``--quick``, the committed page).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(REPO / "tests" / "support"))

from common import arguments, parse  # noqa: E402

from mistaken_submissions import make_submission  # noqa: E402

EMULATION = REPO / "tests" / "support" / "docker_confinement.py"
PAGE = REPO / "docs/benchmarks/grading_in_a_container.md"


def main() -> None:
    parser = arguments(__doc__, "grade only the full solution", repeats=1)
    parser.add_argument("--memory-mb", type=int, default=768)
    parser.add_argument("--cpus", type=float, default=0.5)
    parser.add_argument("--page", type=Path, help=f"default (not with --quick): {PAGE}")
    args = parse(parser)
    if os.geteuid() != 0:
        sys.exit("grading_in_a_container: run it as root (it makes cgroups and drops to Docker's)")
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        solution = make_submission(Path(folder) / "solution")
        cases = {"the full solution": solution}
        if not args.quick:
            hangs = make_submission(Path(folder) / "hangs")
            with open(hangs / "raykit/__init__.py", "a") as module:
                module.write("\nimport time\ntime.sleep(600)\n")
            cases["every test hangs until it is stopped"] = hangs
        for name, submission in cases.items():
            out = Path(folder) / f"{submission.name}.json"
            run = subprocess.run(
                [sys.executable, str(EMULATION), "--memory-mb", str(args.memory_mb),
                 "--cpus", str(args.cpus), "--report", "--",
                 sys.executable, "-m", "raykit_grading", "grade", str(submission), "-o", str(out)],
                capture_output=True, text=True, cwd=folder,
            )  # fmt: skip
            report = re.search(r"wall ([\d.]+) s, peak memory (\d+) MB", run.stderr)
            if report is None or not out.is_file():
                sys.exit(f"grading_in_a_container: {name}: {run.stderr.strip()[-500:]}")
            results = json.loads(out.read_text())
            total = sum(t["max_score"] for t in results["tests"])
            rows.append(
                f"| {name} | {results['score']:g} of {total:g} | exit {run.returncode} | "
                f"{results['extra_data']['sandbox']} | {float(report[1]):.0f} s | "
                f"{report[2]} MB |"
            )
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    lines = [" ".join(["$ python", "benchmarks/grading_in_a_container.py", *sys.argv[1:]]), ""]
    lines += [
        f"`python -m raykit_grading grade` as root under Docker's default confinement with "
        f"{args.memory_mb} MB and {args.cpus:g} of a CPU (tests/support/docker_confinement.py), on "
        f"{os.cpu_count()} CPUs with a load average of {load} as the run ended.",
        "",
        "| submission | score | grade's exit | sandbox | whole grading | the container's peak "
        "memory |",
        "|---|---|---|---|---|---|",
        *rows,
    ]
    print("\n".join(lines[2:]))
    page = args.page or (None if args.quick else PAGE)
    if page is None:
        return
    page.parent.mkdir(parents=True, exist_ok=True)
    page.write_text("\n".join(lines) + "\n")
    print(f"\nwrote {page}")


if __name__ == "__main__":
    main()

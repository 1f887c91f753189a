"""What the grader's sandboxes cost per test, side by side in one run.

    python benchmarks/sandbox_cost.py [--repeats N] [--page docs/benchmarks/sandbox_cost.md]

Times, in turns (medians, :func:`common.medians_in_turns`), of:

* ``bare``: the child's interpreter importing numpy and Pillow, as a plain process with the
  child's environment (one BLAS thread, as in every sandbox);
* ``bubblewrap``: the same command inside the sandbox bubblewrap builds for a test
  (:func:`raykit_grading.sandbox.isolation.sandbox_arguments`: mount, pid, network, ipc, uts
  namespaces);
* ``chroot``: the same command in the sandbox that needs no namespaces (as root only:
  :func:`raykit_grading.sandbox.confine.confine_child`: chroot into the minimal tree, a uid of its
  own, Landlock where the kernel has it, the seccomp filter);
* ``test, bubblewrap`` and ``test, chroot``: a whole :meth:`raykit_grading.sandbox.base.Sandbox.run`
  of the preflight task on the full solution, as each graded test pays it (work folder, inputs,
  for the chroot a copy of the submission into the tree, the sandbox, results over the pipe,
  killing the uid's processes, clean-up);
* ``copy the submission``: the part of a chroot test that puts the solution's ``raykit/`` into
  the tree and removes it (bind mounts need namespaces: hard links where the tree and the
  grader's workspace share a file system, else copies).

And once: building the chroot tree (files, size, seconds), which Gradescope's ``setup.sh``
does when the image is built. The table is printed and written to ``--page`` (by default,
but not with ``--quick``, the committed page).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(REPO))

from common import arguments, medians_in_turns, parse, timer  # noqa: E402

from raykit_grading.sandbox import confine  # noqa: E402
from raykit_grading.sandbox.bubblewrap import Bubblewrap  # noqa: E402
from raykit_grading.sandbox.chroot import Chroot, _link_or_copy  # noqa: E402
from raykit_grading.sandbox.isolation import (  # noqa: E402
    SITE,
    child_environment,
    find_bwrap,
    probe_python,
    sandbox_arguments,
    seccomp_filter,
)
from raykit_grading.sandbox.workspace import Workspace  # noqa: E402

PAGE = REPO / "docs/benchmarks/sandbox_cost.md"
IMPORTS = "import sys; sys.path.insert(0, '{site}'); import numpy, PIL.Image"


def main() -> None:
    parser = arguments(__doc__, "fewer runs", repeats=21)
    parser.add_argument("--page", type=Path, help=f"default (not with --quick): {PAGE}")
    args = parse(parser)
    repeats = 5 if args.quick else args.repeats
    python = probe_python(sys.executable)
    as_root = os.geteuid() == 0
    lines = [" ".join(["$ python", "benchmarks/sandbox_cost.py", *sys.argv[1:]]), ""]
    with Workspace() as workspace:
        submission = workspace / "submission"
        shutil.copytree(REPO / "raykit", submission / "raykit",
                        ignore=shutil.ignore_patterns("__pycache__"))  # fmt: skip
        for path in [submission, *submission.rglob("*")]:
            path.chmod(0o755 if path.is_dir() else 0o644)
        work = Path(tempfile.mkdtemp(dir=workspace))
        (work / "submission").mkdir()
        (work / "tmp").mkdir(mode=0o777)  # the test's own tmp/, bound at /tmp
        work.chmod(0o755)
        site = str(Path(python.packages[0]).parent)
        bare = [python.executable, "-I", "-S", "-c", IMPORTS.format(site=site)]
        boxed = [find_bwrap(), *sandbox_arguments(python, work, submission, as_root),
                 python.executable, "-I", "-S", "-c", IMPORTS.format(site=SITE)]  # fmt: skip
        calls = {
            "bare": lambda: subprocess.run(bare, check=True, env=child_environment("/tmp")),
            "bubblewrap": lambda: subprocess.run(boxed, check=True),
        }
        sandboxes = {"bubblewrap": Bubblewrap(submission, workspace)}
        if as_root:
            built = _tree_once(python)
            sandboxes["chroot"] = Chroot(submission, workspace)
            calls["chroot"], cleanup = _chrooted_imports(python, sandboxes["chroot"])
        for kind, sandbox in sandboxes.items():
            sandbox.check()
            calls[f"test, {kind}"] = lambda sandbox=sandbox: sandbox.run("probe", {}, {})
        if as_root:
            copy_slot, _ = confine.lease_slot(sandboxes["chroot"].tree)
            copy = copy_slot.outside / "submission"
            calls["copy the submission"] = lambda: (
                shutil.copytree(submission, copy, copy_function=_link_or_copy),
                shutil.rmtree(copy),
            )
        try:
            times = medians_in_turns({k: timer(f) for k, f in calls.items()}, repeats)
        finally:
            if as_root:
                cleanup()
                copy_slot.empty()
                copy_slot.release()
    user = "root" if as_root else "a normal user"
    load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
    lines += [f"Per test, as {user}: medians of {repeats} runs of each, in turns, on "
              f"{os.cpu_count()} CPUs with a load average of {load} (1, 5, 15 minutes) "
              "as the run ended.", ""]  # fmt: skip
    lines += ["| what | median | / bare |", "|---|---|---|"]
    for name, seconds in times.items():
        lines.append(f"| {name} | {seconds * 1000:.1f} ms | {seconds / times['bare']:.2f} |")
    if as_root:
        described = sandboxes["chroot"].description
        lines += ["", f"The chroot sandbox here: {described}."]
        lines += [f"Building its tree once: {built[0]:,} files, {built[1] / 2**20:.0f} MB, "
                  f"{built[2]:.1f} s."]  # fmt: skip
    text = "\n".join(lines) + "\n"
    print("\n".join(lines[2:]))
    page = args.page or (None if args.quick else PAGE)
    if page is None:
        return
    page.parent.mkdir(parents=True, exist_ok=True)
    page.write_text(text)
    print(f"\nwrote {page}")


def _tree_once(python) -> tuple[int, int, float]:
    """Build a chroot tree from scratch in a folder of its own: (files, bytes, seconds)."""
    trees = Path(tempfile.mkdtemp(prefix="raykit-trees-"))
    try:
        start = time.perf_counter()
        tree = confine.chroot_tree(python, trees)
        seconds = time.perf_counter() - start
        files = [p for p in tree.rglob("*") if p.is_file() and not p.is_symlink()]
        return len(files), sum(p.stat().st_size for p in files), seconds
    finally:
        shutil.rmtree(trees, ignore_errors=True)


def _chrooted_imports(python, sandbox: Chroot):
    """The import command in the chroot sandbox, as a test's child is confined; and what
    removes its folder and ends its uid's lease."""
    sandbox.check()
    slot, _ = confine.lease_slot(sandbox.tree)
    folder = slot.outside
    (folder / "tmp").mkdir()
    lease = sandbox.uids.lease()
    os.chown(folder / "tmp", lease.uid, lease.uid)
    os.chown(folder, 0, lease.uid)  # as a test's slot is: its uid may read it, no other enter
    os.chmod(folder, 0o750)
    plan = confine.ChildConfinement(
        tree=str(sandbox.tree),
        folder=slot.inside,
        uid=lease.uid,
        rlimits=sandbox._rlimits(),
        landlock_abi=sandbox.landlock,
        landlock_read_execute=tuple(confine.top_entries(sandbox.tree)),
        seccomp=seccomp_filter(),
    )
    command = [python.executable, "-I", "-S", "-c", IMPORTS.format(site=SITE)]
    environment = child_environment(f"{plan.folder}/tmp")

    def run() -> None:
        subprocess.run(
            command, check=True, env=environment, preexec_fn=lambda: confine.confine_child(plan)
        )

    def cleanup() -> None:
        lease.release()
        slot.empty()
        slot.release()

    return run, cleanup


if __name__ == "__main__":
    main()

"""What the benchmarks share: timing by the median, and log-log plots."""

from __future__ import annotations

import argparse
import io
import math
import statistics
import sys
import textwrap
import time
from contextlib import contextmanager
from pathlib import Path


def sized(scene, width: int, height: int):
    """``scene`` with its camera's image ``width`` x ``height`` pixels, all else the same."""
    from dataclasses import replace

    return replace(scene, camera=replace(scene.camera, width=width, height=height))


def processor() -> tuple[str, str | None]:
    """The processor's model name ("" if /proc/cpuinfo gives none) and the widest vector
    instruction set it has, "AVX-512", "AVX2" or None (neither), from the first processor's
    entry in /proc/cpuinfo."""
    info = Path("/proc/cpuinfo").read_text() if Path("/proc/cpuinfo").exists() else ""
    fields = dict(
        line.split(":", 1) for line in reversed(info.splitlines()) if ":" in line
    )  # the first processor's, by key
    fields = {key.strip(): value.strip() for key, value in fields.items()}
    flags = set(fields.get("flags", "").split())
    widest = "AVX-512" if "avx512f" in flags else "AVX2" if "avx2" in flags else None
    return fields.get("model name", ""), widest


def numba_cpu(name: str) -> dict[str, str]:
    """The environment in which numba, as it is imported, compiles for the CPU ``name`` (e.g.
    "haswell": AVX2 without AVX-512) with that CPU's own features (NUMBA_CPU_FEATURES empty),
    not this machine's, which numba would otherwise add; "native": none, this machine's."""
    return {} if name == "native" else {"NUMBA_CPU_NAME": name, "NUMBA_CPU_FEATURES": ""}


def arguments(doc: str, quick: str, repeats: int | None = 5) -> argparse.ArgumentParser:
    """The options every benchmark takes, ``--quick`` and ``--repeats`` (its default
    ``repeats``; None: no ``--repeats``, for a benchmark that times nothing); ``doc`` is the
    script's docstring, whose first paragraph describes it."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0], allow_abbrev=False)
    parser.add_argument("--quick", action="store_true", help=quick)
    if repeats is not None:
        parser.add_argument(
            "--repeats", type=int, default=repeats, help="runs per variant (median)"
        )
    return parser


def parse(parser: argparse.ArgumentParser) -> argparse.Namespace:
    """Parse the command line and print it first, as ``$ python benchmarks/NAME ARGS``, so a
    saved run says how to repeat it."""
    args = parser.parse_args()
    print(command_line() + "\n")
    return args


def command_line() -> str:
    """This benchmark's command line as ``$ python benchmarks/NAME ARGS``."""
    return " ".join(["$ python", f"benchmarks/{Path(sys.argv[0]).name}", *sys.argv[1:]])


class _Tee(io.TextIOBase):
    """A text stream that writes to ``stream`` and keeps a copy."""

    def __init__(self, stream) -> None:
        self.stream, self.copy = stream, io.StringIO()

    def write(self, text: str) -> int:
        self.copy.write(text)
        return self.stream.write(text)

    def flush(self) -> None:
        self.stream.flush()


@contextmanager
def page_of_output(page: Path | None):
    """Print as usual inside; if all went well and ``page`` is not None, write the command line
    and everything printed to ``page`` (the benchmark's page under docs/benchmarks/)."""
    tee = _Tee(sys.stdout)
    sys.stdout = tee
    try:
        yield
    finally:
        sys.stdout = tee.stream
    if page is not None:
        page.parent.mkdir(parents=True, exist_ok=True)
        page.write_text(command_line() + "\n\n" + tee.copy.getvalue().strip("\n") + "\n")
        print(f"\nwrote {page}")


def seconds(value: float | None, decimals: int = 0) -> str:
    """A time for a table: milliseconds below 10 s, else seconds; None is "not run"."""
    if value is None:
        return "not run"
    return f"{value * 1000:.{decimals}f} ms" if value < 10 else f"{value:.{decimals}f} s"


def median_time(function, repeats: int):
    """(the last result, the median wall time in seconds) of ``repeats`` calls."""
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - start)
    return result, statistics.median(times)


def interleaved_medians(calls: dict, repeats: int, warm: bool = False) -> dict:
    """The median wall time in seconds of each of ``calls`` (key: function), taken in turns
    (:func:`medians_in_turns`)."""
    return medians_in_turns({key: timer(f) for key, f in calls.items()}, repeats, warm)


def timer(function):
    """``function`` as a timer for :func:`medians_in_turns`: it calls ``function`` once and
    returns the seconds that took."""

    def timed() -> float:
        start = time.perf_counter()
        function()
        return time.perf_counter() - start

    return timed


def medians_in_turns(timers: dict, repeats: int, warm: bool = False) -> dict:
    """The median of the seconds each of ``timers`` (key: function that does its work once and
    returns the seconds it took, by its own clock: a child process times its own) reports,
    taken in turns: each round calls every timer once, so a burst of load from the machine's
    neighbours falls on all of them alike, and their ratios hold better than their times. Every
    other round goes in reverse order, so that none always comes right after the same one: in
    a fixed order, whole processes of ``raykit render`` that came right after a compiled render
    of 1,000 spheres at 1080p took 1.3 times as long, whatever they did. ``warm``: each timed
    call comes right after an untimed one of the same timer, so that it finds its data in the
    caches as it would in a run of its own (rendered in turns with sphereflake 6, whose arrays
    fill the caches, sphereflake 4 took longer without the untimed call than with it)."""
    times: dict = {key: [] for key in timers}
    keys = list(timers)
    for round_ in range(repeats):
        for key in keys if round_ % 2 == 0 else keys[::-1]:
            if warm:
                timers[key]()
            times[key].append(timers[key]())
    return {key: statistics.median(values) for key, values in times.items()}


def loglog_plot(
    path: Path,
    series: dict[str, tuple[list, list, str]],
    xlabel: str,
    ylabel: str,
) -> None:
    """One log-log line per ``label: (xs, ys, style)``, written to ``path``, the legend under
    the axes: inside them, wherever it went, it lay on some run's line or markers."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from raykit.io.images import save_figure

    figure, ax = plt.subplots(
        figsize=(5, 3.5 + 0.35 * math.ceil(len(series) / 2)), layout="constrained"
    )
    for label, (xs, ys, style) in series.items():
        ax.loglog(xs, ys, style, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    figure.legend(loc="outside lower center", ncol=2)
    save_figure(figure, path)
    plt.close(figure)
    print(f"\nwrote {path}")


def bar_plot(
    path: Path,
    groups: list[str],
    series: dict[str, list],
    ylabel: str,
    title: str = "",
    log: bool = False,
) -> None:
    """A panel of bars per group, one colour per ``label: values`` in seconds (None: no bar),
    drawn in milliseconds from zero (``log``: on a log scale shared by the panels, for times
    that span decades) with each bar's value on it, written to ``path``; in two rows of as many
    panels as it takes, four a row at least, the legend below them. Panels, not one axis of many
    groups: with eight groups of five bars, one axis's labels ran into each other and its legend
    covered bars. Two rows, not more: a figure fitted to the projector (its text a share of its
    height, :func:`raykit.io.images.fit_for_projector`) squeezed four rows of panels until their
    titles ran into each other."""

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    from raykit.io.images import save_figure

    columns = max(1, min(len(groups), max(4, math.ceil(len(groups) / 2))))
    rows = max(1, math.ceil(len(groups) / columns))
    figure, axes = plt.subplots(
        rows,
        columns,
        figsize=(2.4 * columns, 2.3 * rows + 0.5 + 0.25 * math.ceil(len(series) / 2)),
        sharey=log,
        squeeze=False,
        layout="constrained",
    )
    for g, ax in enumerate(axes.flat):
        if g >= len(groups):
            ax.set_visible(False)
            continue
        for k, (label, values) in enumerate(series.items()):
            if values[g] is not None:
                bars = ax.bar(k, values[g] * 1000, 0.8, color=f"C{k}", label=label)
                ax.bar_label(bars, fmt="%.0f", fontsize=7, padding=1)
        # a scene's file stem may break after an underscore, as a phrase after a space
        name = textwrap.fill(groups[g].replace("_", "_ "), 16, break_long_words=False)
        ax.set_title(name.replace("_ ", "_"), fontsize=8)
        ax.set_xticks([])
        ax.tick_params(labelsize=7)
        ax.set_xlim(-0.6, len(series) - 0.4)
        if log:
            ax.set_yscale("log")
        ax.margins(y=0.15)  # room for the labels on the tallest bars
    if log:  # a log scale's margin is a share of its decades: room for a label above instead
        drawn = [v * 1000 for values in series.values() for v in values if v is not None]
        axes.flat[0].set_ylim(top=max(drawn) * 10)
    figure.supylabel(ylabel, fontsize=8)
    if title:
        figure.suptitle(title, fontsize=9)
    figure.legend(
        [Patch(color=f"C{k}") for k in range(len(series))],
        list(series),
        loc="outside lower center",
        ncol=2,
        fontsize=8,
    )
    save_figure(figure, path)
    plt.close(figure)
    print(f"\nwrote {path}")

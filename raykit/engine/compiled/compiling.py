"""How the kernels are compiled: numba's options, the cache on disk, and the progress line.

Repeats no reference module: this is the machinery the others share. A kernel run once per job
or per tile is its own numba function (``@njit(**KERNEL)``), compiled the first time a render
needs it, with the kernels it calls, each once, and cached on disk by itself; a kernel run once
per ray is compiled once too, and LLVM copies its code into the kernels that call it where its
own rule finds that it pays (``ONE_RAY``), or always (``INLINED``). So a flat
scene compiles only the flat scene's kernels (:func:`raykit.engine.compiled.render.trace_flat`
names no shading kernel), a lit scene adds its own, and a scene with mirrors its mirror rays
(:func:`raykit.engine.compiled.shading.mirror_rays`).

The cache lives in a folder named after a hash of the package's sources, its folder, and the
reference modules the kernels repeat or read a constant of
(:func:`raykit.engine.choice.cache_folder`, from the twin table, :mod:`.twins`): editing a
kernel, or a constant it freezes, makes a new folder, so no kernel compiled from older source
is ever served (numba keeps no account of which kernels a cached kernel calls, nor of the
globals it froze). numba writes each kernel's files whole (a temporary file, then a rename),
so a compile stopped part way, by Ctrl-C or otherwise, leaves the kernels it finished, usable,
and the next run compiles the rest. A marker per entry point (:func:`finished`) says that one
render compiled everything it needs: :func:`marked` and
:func:`raykit.engine.choice.compiled_once` read it.

While a render compiles, a progress line on a terminal names the kernel at hand and how much
is left, by the seconds each kernel took when ``python benchmarks/compile_time.py`` last
measured them (``compile_seconds.json``, written by that command), scaled to this machine's
pace so far; off a terminal (a CI log, a redirected file), one line says the compile started
and one that it ended, how long it took and which kernels it compiled.
"""

from __future__ import annotations

import json
import sys
import threading
import time
from contextlib import contextmanager
from pathlib import Path
from typing import TextIO

import numba
from numba.core import event

from raykit.engine.choice import cache_folder, marker

CACHE = cache_folder()  # keyed on the sources the kernels are made from, and where they are
numba.config.CACHE_DIR = str(CACHE) if CACHE is not None else ""  # read as kernels are made
# a kernel that makes arrays: cached on disk; x / 0 gives inf as numpy does; no GIL held
MAKES_ARRAYS = dict(cache=CACHE is not None, error_model="numpy", nogil=True)
# every other kernel: the same, without reference counts (numba's _nrt=False). It only reads
# and writes arrays its caller holds, and counting each array in and out of every call, on
# counters that every worker shares, costs more than most kernels' arithmetic (python
# benchmarks/thresholds.py times the kernels with them on: docs/benchmarks/thresholds.md)
KERNEL = dict(MAKES_ARRAYS, _nrt=False)
# a kernel run once per ray, or per object a ray meets, must not stay a call in the loops: a
# call passes the scene's arrays as a hundred numbers or more, more work than such a kernel
# does, and inlined, a loop of it becomes vector instructions. Each is compiled once, a kernel
# of its own, and LLVM inlines its code where it is called: where LLVM's rule finds that it pays
# (ONE_RAY; benchmarks/compile_time.py lists the calls it leaves), or always (INLINED, numba's
# forceinline: LLVM's alwaysinline) for those LLVM would leave as calls in a hot loop, the large
# ones (nearest_hit, keep_nearer, primary_ray, surface_color, bounce_on, and shade and
# sample_numbers, which a distributed render calls once a sample) and the box tests (enters,
# box_apart, sphere_apart). Not numba's inline="always", which copies the callee's code into
# its caller at each place it is called, its own callees' copies with it, in time that grows as
# the square of the callee's size (numba issue 8989), and types every copy anew: shade holds
# bounce_on, which holds surface_color, each with the tree walk, and their copies were most of
# a distributed scene's first use
ONE_RAY = KERNEL
INLINED = dict(KERNEL, forceinline=True)
# the one job of an entry point that makes no array (a KERNEL, its rooms made before its call):
# numba's inline="always" copies it into the entry point, which calls it once. A kernel of its
# own, it is made twice: as itself, and again in the entry point that calls it (numba links a
# callee's code into each caller and makes machine code of the whole), and a job holds most of a
# render's code. Not into an entry point that makes arrays: copied there, its arrays would count
# their references (benchmarks/compile_time.py times each kernel's compile)
JOB = dict(KERNEL, inline="always")
SECONDS_TABLE = Path(__file__).with_name("compile_seconds.json")
MESSAGE = "compiling raykit's fast kernels, once"
PRIOR_SECONDS = 5.0  # how long the table's own pace counts in the time left (seconds_left)


def measured_seconds() -> dict[str, dict[str, float]]:
    """Per entry point (``trace_flat``, ``trace_lit``, ``trace_mirrors``, ``trace_sampled``),
    the seconds each kernel's own compile took (its callees' not counted) when
    benchmarks/compile_time.py last ran; empty if no table."""
    try:
        return json.loads(SECONDS_TABLE.read_text())
    except (OSError, ValueError):
        return {}


class CompileClock(event.Listener):
    """Listens to numba's compile events: each kernel's own compile seconds (``own``, by
    name), and a progress line on standard error from the first compile on (``bar``), moved
    on by each kernel's measured seconds (:func:`measured_seconds`): all of them as it
    finishes, and while it compiles, the seconds it has taken so far, up to them
    (:meth:`progress`), and the time left (:meth:`seconds_left`). A kernel credited only as
    it ended made the line jump from a few seconds left to many minutes and back."""

    def __init__(self, entry: str, show: bool, stream: TextIO | None = None):
        self.expected = measured_seconds().get(entry, {})
        self.show = show
        self.stream = stream  # None: standard error
        self.own: dict[str, float] = {}
        self.open: list[list] = []  # [name, started, seconds of its callees' compiles]
        self.bar = None
        self.started = None  # when the first kernel's compile started
        self.done = 0.0
        self.interrupted = False  # a Ctrl-C swallowed on its way (see compile_clock)

    def on_start(self, ev) -> None:
        name = _kernel_name(ev)
        if self.started is None:
            self.started = time.perf_counter()
        if self.show and self.bar is None:
            self.bar = _progress_line(self.total, self.stream)
        self.open.append([name, time.perf_counter(), 0.0])
        self._show()
        self._stop_if_interrupted()

    def on_end(self, ev) -> None:
        if not self.open:  # a Ctrl-C came in its start event before it was counted
            return
        name, started, inner = self.open.pop()
        took = time.perf_counter() - started
        if name is None:  # a helper of numba's: its time is its caller's own
            took = inner
        else:
            self.own[name] = self.own.get(name, 0.0) + took - inner
        if self.open:
            self.open[-1][2] += took
        if name is not None:
            self.done += self.expected.get(name, 0.0)
        self._show()
        self._stop_if_interrupted()

    def _stop_if_interrupted(self) -> None:
        """Raise the Ctrl-C that was swallowed, now that numba is in Python, between kernels."""
        if self.interrupted:
            self.interrupted = False
            raise KeyboardInterrupt

    def progress(self, now: float) -> float:
        """Seconds of the table done at time ``now`` (:func:`time.perf_counter`): the
        finished kernels' measured seconds, and each open kernel's own seconds so far (not
        those in the callee it is compiling), up to its measured seconds."""
        done, until = self.done, now
        for name, started, inner in reversed(list(self.open)):  # the ticker thread reads it too
            if name is not None:
                done += min(max(0.0, until - started - inner), self.expected.get(name, 0.0))
                until = started
        return done

    def seconds_left(self, now: float) -> float:
        """The table's seconds not yet done at time ``now``, at this machine's pace: the
        seconds the compile has taken per second of the table done. That pace starts as the
        table's own (1) and becomes this machine's as the compile goes on, PRIOR_SECONDS
        standing for the table's: (elapsed + PRIOR_SECONDS) / (done + PRIOR_SECONDS). (The
        pace alone, elapsed / done, was wild in the first seconds, with little done.)"""
        done = self.progress(now)
        elapsed = now - self.started if self.started is not None else 0.0
        pace = (elapsed + PRIOR_SECONDS) / (done + PRIOR_SECONDS)
        return max(0.0, self.total - done) * pace

    @property
    def total(self) -> float:
        """The table's seconds for the entry point: all of its kernels'."""
        return sum(self.expected.values())

    def finish(self) -> None:
        """The compile is over: the line at its end. (Kernels loaded from the cache, which a
        render of another entry point left, send no event: without this, the line would stop
        short of them.)"""
        if self.bar is not None and self.bar.total:
            self.bar.n = self.bar.total
            self.bar.set_postfix_str(f"~{self.bar.format_interval(0)} left", refresh=False)
            self.bar.refresh()

    def close(self) -> None:
        """The line's end: off a terminal, the one line that says how long the compile took and
        which of the package's kernels it compiled."""
        if isinstance(self.bar, LogLine):
            self.bar.close(f"{len(self.own)} kernels: {', '.join(self.own)}")
        elif self.bar is not None:
            self.bar.close()

    def _show(self) -> None:
        """The innermost of the package's kernels being compiled, and the progress, on the
        progress line."""
        if self.bar is None:
            return
        if self.bar.total:
            now = time.perf_counter()
            self.bar.n = min(self.bar.total, round(self.progress(now), 1))
            left = self.bar.format_interval(round(self.seconds_left(now)))
            self.bar.set_postfix_str(f"~{left} left", refresh=False)
        names = [name for name, _, _ in self.open if name is not None]
        if names:
            self.bar.set_description_str(f"{MESSAGE}: {names[-1]}", refresh=False)
        self.bar.refresh()


def _kernel_name(ev) -> str | None:
    """The kernel a compile event is about, or None for numba's own helpers (which it compiles
    for a kernel that uses them: their seconds count as that kernel's)."""
    function = ev.data["dispatcher"].py_func
    return function.__name__ if function.__module__.startswith(__package__) else None


def _progress_line(total: float, stream: TextIO | None = None):
    """The compile's progress line (:func:`moving_line`): on a terminal, a bar that moves; in a
    log, a line at the start and one at the end."""
    known = "{desc} {percentage:3.0f}%|{bar:20}| [{elapsed}{postfix}]"  # postfix: ", ~0:42 left"
    return moving_line(  # with no table of seconds: what it compiles, and how long so far
        MESSAGE,
        round(total, 1) if total > 0 else None,
        stream,
        unit="s",
        bar_format=known if total > 0 else "{desc} [{elapsed}]",
        leave=True,
    )


class LogLine:
    """A progress line for a log, with the part of tqdm's interface that :class:`CompileClock`
    uses (``n``, ``total``, ``set_description_str``, ``set_postfix_str``, ``refresh``,
    ``format_interval``, ``close``): one line as it is made, one as it is closed (how long the
    work took, and a summary), and nothing between. (Here, not beside the bars of
    :mod:`raykit.io.progress`: the engine imports nothing of raykit.io, tests/test_layout.py.)"""

    def __init__(self, description: str, total: float | None, stream: TextIO) -> None:
        self.message, self.total, self.stream = description, total, stream
        self.n: float = 0.0
        self.started = time.perf_counter()
        self.closed = False
        about = f", about {self.format_interval(round(total))}" if total else ""
        print(f"{description}: started{about}", file=stream, flush=True)

    def set_description_str(self, text: str, refresh: bool = True) -> None:
        """Nothing to show until the end."""

    def set_postfix_str(self, text: str, refresh: bool = True) -> None:
        """Nothing to show until the end."""

    def refresh(self) -> None:
        """Nothing to show until the end."""

    @staticmethod
    def format_interval(seconds: float) -> str:
        """``seconds`` as tqdm writes them: mm:ss, or h:mm:ss."""
        minutes, seconds = divmod(int(seconds), 60)
        hours, minutes = divmod(minutes, 60)
        return f"{hours}:{minutes:02d}:{seconds:02d}" if hours else f"{minutes:02d}:{seconds:02d}"

    def close(self, summary: str = "") -> None:
        """The line at the end, once: how long since the start, and ``summary``."""
        if self.closed:
            return
        self.closed = True
        took = self.format_interval(time.perf_counter() - self.started)
        print(f"{self.message}: ended after {took}{summary and f' ({summary})'}",
              file=self.stream, flush=True)  # fmt: skip


def on_a_terminal(stream: TextIO) -> bool:
    """Whether ``stream`` is an open terminal (a closed one, or one with no isatty, is not)."""
    try:
        return stream.isatty()
    except (AttributeError, ValueError):
        return False


def moving_line(description: str, total: float | None, stream: TextIO | None = None, **options):
    """A progress line for work that says it is under way wherever it runs: on a terminal
    (``stream``, default stderr), a tqdm bar of ``total`` (None: unknown) that moves with
    carriage returns, made with tqdm's ``options``; elsewhere (a CI log, a redirected file) a
    :class:`LogLine`, a line at the start and one at the end."""
    stream = sys.stderr if stream is None else stream
    if not on_a_terminal(stream):
        return LogLine(description, total, stream)
    from tqdm import tqdm

    return tqdm(total=total, desc=description, file=stream, **options)


@contextmanager
def compile_clock(entry: str, show: bool = True):
    """Around a call that may compile: the :class:`CompileClock` of ``entry`` listening to
    numba, with a thread that redraws the progress line each second (numba's compiles leave
    Python for long stretches of LLVM, where no event comes).

    LLVM calls back into Python as it finishes each kernel (llvmlite's object cache, through
    ctypes), and a Ctrl-C that lands in such a callback is not raised: ctypes reports it to
    :func:`sys.unraisablehook` and carries on, and the compile would run to its end. So while
    the clock runs, that hook notes a swallowed Ctrl-C, and the clock raises it at the next
    kernel's start or end, or as the call returns."""
    clock = CompileClock(entry, show)
    stop = threading.Event()
    unraisable = sys.unraisablehook

    def note_ctrl_c(report) -> None:
        if isinstance(report.exc_value, KeyboardInterrupt):
            clock.interrupted = True
        else:
            unraisable(report)

    def redraw():
        while not stop.wait(1.0):
            clock._show()

    ticker = threading.Thread(target=redraw, daemon=True)
    ticker.start()
    sys.unraisablehook = note_ctrl_c
    try:
        with event.install_listener("numba:compile", clock):
            yield clock
        clock._stop_if_interrupted()
        clock.finish()
    finally:
        sys.unraisablehook = unraisable
        stop.set()
        ticker.join()
        clock.close()


M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc's malloc.h


def keep_freed_memory() -> None:
    """Have the C library's malloc keep large blocks it frees for the next ones, where it is
    glibc's: a render's outputs (a 1080p picture's colours, objects and distances are 83 MB of
    float64) are otherwise each time new pages from the system, every page a fault and zeroed
    before the kernel writes it, a measurable share of a render. Dr.Jit keeps its own memory for
    the same reason. Freed memory then stays with the process, for its next render, rather than
    going back to the system. A no-op where malloc is another library's."""
    import ctypes
    import ctypes.util

    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name)
    except (OSError, TypeError):
        return
    if not hasattr(libc, "gnu_get_libc_version"):  # glibc's, whose mallopt takes these
        return
    largest = 1 << 30  # blocks below this come from the heap, which keeps what is freed
    for option in (M_MMAP_THRESHOLD, M_TRIM_THRESHOLD):
        libc.mallopt(option, largest)


def finished(entry: str, seconds: float) -> None:
    """Mark ``entry``'s kernels compiled and cached (after its first render)."""
    if CACHE is not None:
        marker(entry, CACHE).write_text(f"{seconds:.1f} s\n")


def marked(entry: str) -> bool:
    """Whether ``entry``'s kernels are marked compiled and cached (:func:`finished`)."""
    return CACHE is not None and marker(entry, CACHE).exists()

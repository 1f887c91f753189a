"""How the kernels are compiled (raykit.engine.compiled.compiling): the progress line and Ctrl-C."""

from __future__ import annotations

import io
import sys

import numba
import pytest


@pytest.fixture
def fake_compile(monkeypatch):
    """The compile clock's module, with a clock that stands still (``now[0]``, seconds: move it
    by hand), and ``event(name)``, a numba compile event of one of the package's kernels."""
    from types import SimpleNamespace

    from raykit.engine.compiled import compiling

    now = [100.0]
    monkeypatch.setattr(compiling.time, "perf_counter", lambda: now[0])

    def event(name):
        kernel = SimpleNamespace(__name__=name, __module__="raykit.engine.compiled.render")
        return SimpleNamespace(data={"dispatcher": SimpleNamespace(py_func=kernel)})

    return compiling, now, event


def test_the_progress_line_counts_a_kernel_as_it_compiles_up_to_its_measured_seconds(
    fake_compile,
):
    """The line moves while a long kernel compiles, never past the kernel's measured seconds
    before it ends, and the whole table once every kernel has ended."""
    compiling, now, event = fake_compile
    clock = compiling.CompileClock("trace_lit", show=False)
    clock.expected = {"lit_job": 20.0, "light_lanes": 6.0}
    clock.on_start(event("lit_job"))
    now[0] += 3.0
    assert clock.progress(now[0]) == 3.0  # lit_job's own seconds so far
    clock.on_start(event("light_lanes"))
    now[0] += 2.0
    assert clock.progress(now[0]) == 3.0 + 2.0  # lit_job's 3 s are kept, and light_lanes' 2 s
    now[0] += 10.0
    assert clock.progress(now[0]) == 3.0 + 6.0  # up to its measured 6 s, however slow this is
    clock.on_end(event("light_lanes"))
    assert clock.progress(now[0]) == 6.0 + 3.0  # lit_job's own 3 s, not the 12 s in its callee
    now[0] += 30.0
    assert clock.progress(now[0]) == 6.0 + 20.0
    clock.on_end(event("lit_job"))
    assert clock.progress(now[0]) == 26.0
    assert clock.own == {"light_lanes": 12.0, "lit_job": 33.0}


class Terminal(io.StringIO):
    """A stream that says it is a terminal, as a user's stderr is."""

    def isatty(self):
        return True


def test_the_line_ends_full_when_some_of_the_tables_kernels_came_from_the_cache(
    fake_compile, monkeypatch
):
    compiling, now, event = fake_compile
    monkeypatch.setattr(compiling, "measured_seconds", lambda: {"trace_mirrors": {
        "mirror_rays": 7.0, "light_lanes": 4.0}})  # fmt: skip
    terminal = Terminal()
    clock = compiling.CompileClock("trace_mirrors", show=True, stream=terminal)
    clock.on_start(event("mirror_rays"))  # light_lanes is cached (trace_lit compiled it)
    now[0] += 7.0
    clock.on_end(event("mirror_rays"))
    assert clock.bar.n == 7.0
    clock.finish()
    assert clock.bar.n == clock.bar.total == 11.0
    clock.bar.close()
    assert "100%" in terminal.getvalue()


def test_off_a_terminal_a_compile_writes_a_line_at_its_start_and_one_at_its_end(fake_compile):
    """Into a CI log or a redirected file, no carriage return: the end's line says how long the
    compile took and names the kernels it compiled."""
    compiling, now, event = fake_compile
    log = io.StringIO()
    clock = compiling.CompileClock("trace_flat", show=True, stream=log)
    clock.expected = {"flat_job": 20.0, "primary_rays": 5.0}
    for name in ("flat_job", "primary_rays"):
        clock.on_start(event(name))
        for _ in range(30):  # the ticker redraws each second
            now[0] += 1.0
            clock._show()
    clock.on_end(event("primary_rays"))
    clock.on_end(event("flat_job"))
    clock.finish()
    clock.close()
    clock.close()  # once only
    start, end = log.getvalue().splitlines()
    assert "\r" not in log.getvalue()
    assert start == f"{compiling.MESSAGE}: started, about 00:25"
    assert end == f"{compiling.MESSAGE}: ended after 01:00 (2 kernels: primary_rays, flat_job)"


def test_the_time_left_starts_at_the_tables_seconds_and_follows_this_machines_pace(
    fake_compile, monkeypatch
):
    compiling, now, event = fake_compile
    monkeypatch.setattr(compiling, "PRIOR_SECONDS", 5.0)
    clock = compiling.CompileClock("trace_lit", show=False)
    clock.expected = {"bin_by_tile": 1.0, "lit_job": 29.0}
    clock.on_start(event("bin_by_tile"))
    assert clock.seconds_left(now[0]) == 30.0  # nothing known yet of this machine: the table's
    now[0] += 4.0  # the first kernel takes longer than the table's 1 s (numba warms up)
    # the pace alone, 4 s for 1 s done, would say 29 x 4 = 116 s left
    assert clock.seconds_left(now[0]) == 29.0 * (4.0 + 5.0) / (1.0 + 5.0)
    clock.on_end(event("bin_by_tile"))
    clock.on_start(event("lit_job"))
    now[0] += 10.0
    assert clock.seconds_left(now[0]) == 19.0 * (14.0 + 5.0) / (11.0 + 5.0)
    now[0] += 19.0
    clock.on_end(event("lit_job"))
    assert clock.seconds_left(now[0]) == 0.0


def _callback_interrupted_by_ctrl_c():
    """A call from C into Python that a Ctrl-C interrupts, as llvmlite's object-cache callback
    was as LLVM finished a kernel: ctypes reports the KeyboardInterrupt to sys.unraisablehook
    and returns as if nothing happened."""
    import ctypes

    @ctypes.CFUNCTYPE(None)
    def callback():
        raise KeyboardInterrupt

    callback()


def test_a_ctrl_c_swallowed_by_a_callback_from_llvm_stops_the_compile_at_the_next_kernel():
    from raykit.engine.compiled.compiling import compile_clock

    @numba.njit(cache=False)
    def next_kernel(x):
        return x + 1

    hook = sys.unraisablehook
    with pytest.raises(KeyboardInterrupt):
        with compile_clock("trace_flat", show=False) as clock:
            _callback_interrupted_by_ctrl_c()
            assert clock.interrupted  # swallowed, and noted
            next_kernel(1)
    assert not next_kernel.signatures  # stopped as its compile started
    assert sys.unraisablehook is hook


def test_a_ctrl_c_swallowed_in_the_last_kernel_is_raised_as_the_call_returns():
    from raykit.engine.compiled.compiling import compile_clock

    with pytest.raises(KeyboardInterrupt):
        with compile_clock("trace_flat", show=False):
            _callback_interrupted_by_ctrl_c()


def test_any_other_error_a_callback_swallows_goes_to_the_hook_that_was_there(monkeypatch):
    import ctypes

    from raykit.engine.compiled.compiling import compile_clock

    reported = []
    monkeypatch.setattr(sys, "unraisablehook", lambda report: reported.append(report.exc_value))

    @ctypes.CFUNCTYPE(None)
    def callback():
        raise ValueError("not a Ctrl-C")

    with compile_clock("trace_flat", show=False) as clock:
        callback()
    assert not clock.interrupted
    assert [str(error) for error in reported] == ["not a Ctrl-C"]


def test_a_moving_line_moves_on_a_terminal_and_elsewhere_writes_two_lines(fake_compile):
    compiling, now, _ = fake_compile
    terminal, log = Terminal(), io.StringIO()
    for stream in (terminal, log):
        line = compiling.moving_line("compiling", 30.0, stream, bar_format="{desc} {n}/{total}")
        for step in range(5):
            line.n = step
            line.set_description_str(f"compiling: kernel {step}")
            line.refresh()
        now[0] += 75.0
        line.close()
    assert terminal.getvalue().count("\r") >= 5 and "kernel 4" in terminal.getvalue()
    assert log.getvalue().splitlines() == [
        "compiling: started, about 00:30",
        "compiling: ended after 01:15",
    ]


def test_a_kernel_inlined_always_is_typed_once_and_leaves_no_call_in_the_machine_code():
    """An INLINED kernel is numba's to compile once, a kernel of its own, and LLVM's to copy
    where it is called: numba's own inline="always" copied it into its caller at each call and
    typed each copy anew, which was most of a distributed scene's first use."""
    import re

    import numpy as np
    from numba.core import ir, types

    from raykit.engine.compiled.bvh import enters

    @numba.njit(cache=False)
    def nearer_of_two(lower, upper, node, t_max):  # enters at two places
        entered_a, near_a = enters(-2.0, 0.0, 0.0, 1.0, np.inf, np.inf, lower, upper, node, t_max)
        entered_b, near_b = enters(2.0, 0.0, 0.0, -1.0, np.inf, np.inf, lower, upper, node, t_max)
        return entered_a and entered_b, min(near_a, near_b)

    box = np.array([[-1.0, -1.0, -1.0]]), np.array([[1.0, 1.0, 1.0]])
    assert nearer_of_two(*box, 0, np.inf) == (True, 1.0)
    signature = nearer_of_two.signatures[0]
    typed = nearer_of_two.overloads[signature].type_annotation
    called = [
        typed.typemap[call.func.name]
        for call in typed.calltypes
        if isinstance(call, ir.Expr) and call.op == "call"
    ]
    kernels = [f for f in called if isinstance(f, types.Dispatcher) and f.dispatcher is enters]
    assert len(kernels) == 2  # called, not its operations copied in
    symbols = {enters.overloads[each].fndesc.mangled_name for each in enters.signatures}
    left = re.findall(r'call [^@\n]*@"?(_ZN[^"(\s]+)', nearer_of_two.inspect_llvm(signature))
    assert symbols and not symbols & set(left)  # and in the machine code, no call of it


def test_an_entry_point_counts_no_references_and_its_job_is_copied_into_it():
    """An entry point makes no array (its workers' rooms are made before its call) and so counts
    no references, and its one job (JOB) is copied into it: compiled as a kernel of its own, a
    job, most of a render's code, was made twice, as itself and inside the entry point."""
    import numpy as np

    from raykit.engine.compiled import render
    from raykit.engine.compiled.compiling import JOB, KERNEL

    entries = [render.trace_flat, render.trace_lit, render.trace_sampled, render.trace_moving]
    jobs = [render.flat_job, render.lit_job, render.sampled_lanes, render.sampled_job]
    assert all(entry.targetoptions.get("_nrt") is False for entry in entries)
    assert all(job.targetoptions.get("inline") == "always" for job in jobs)

    @numba.njit(**dict(JOB, cache=False))
    def job(values, i):
        values[i] = 2.0 * values[i]

    @numba.njit(**dict(KERNEL, cache=False))
    def entry(values, room):
        for i in range(len(values)):
            room[0] = values[i]
            job(values, i)

    values = np.arange(4.0)
    entry(values, np.empty(1))
    assert values.tolist() == [0.0, 2.0, 4.0, 6.0]
    assert not job.overloads  # copied, never compiled as a kernel of its own
    code = entry.inspect_llvm(entry.signatures[0])
    assert "NRT_incref" not in code and "NRT_decref" not in code

"""The threads that run a render's workers: how many (:func:`worker_count`), how they share the
jobs (:func:`shares`), the pool (:func:`thread_pool`), and one call of an entry point of
:mod:`~raykit.engine.compiled.render` on all of them (:func:`run`), compiled first where the
cache has none. Plain Python: the workers are the kernels, each taking its jobs
(:func:`.jobs.grain_taken`)."""

from __future__ import annotations

import ctypes
import functools
import os
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

import numba
import numpy as np

from raykit.engine.compiled.compiling import compile_clock, finished, marked
from raykit.engine.compiled.jobs import Work

GRAINS_PER_WORKER = 16  # takes of jobs per worker: few enough that taking costs nothing, and
# many enough that a worker slowed by other work leaves little for the others to wait on


def worker_count(jobs: np.ndarray) -> int:
    """How many workers share ``jobs`` (one at least): one per numba thread
    (numba.get_num_threads(), which numba.set_num_threads sets), and not more than the jobs."""
    return max(1, min(numba.get_num_threads(), len(jobs)))


def shares(jobs: np.ndarray) -> Work:
    """How the workers of one call share ``jobs (J,)``: a :class:`~.jobs.Work` with the jobs a
    worker takes at a time, GRAINS_PER_WORKER takes a worker, and a counter of none taken yet."""
    grain = max(1, len(jobs) // (worker_count(jobs) * GRAINS_PER_WORKER))
    return Work(jobs, grain, np.zeros(1, dtype=np.int64))


READY: set[str] = set()  # entry points compiled or loaded from the cache in this process


def run(name, entry, *arguments, rooms: Callable[[], tuple]) -> None:
    """``entry(*arguments)`` on :func:`worker_count` threads at once (:func:`run_workers`), sharing
    the jobs of its last argument, a :class:`~.jobs.Work` (:func:`shares`); each worker's call
    takes more arguments, those of ``rooms()``, made for it alone. The first time in a
    process whose cache has no marker for ``name``
    (:func:`~raykit.engine.compiled.compiling.marked`), it is compiled first, in this thread, with
    the progress line of its compile (:func:`~raykit.engine.compiled.compiling.compile_clock`), and
    then marked (the kernels that make the rooms compile with it, as they are first called)."""
    workers = worker_count(arguments[-1].jobs)

    def each_worker() -> list[tuple]:
        return [(*arguments, *rooms()) for _ in range(workers)]

    if name not in READY and not marked(name):
        started = time.perf_counter()
        with compile_clock(name):
            each = each_worker()
            entry.compile(tuple(entry.typeof_pyval(argument) for argument in each[0]))
        finished(name, time.perf_counter() - started)
    else:
        each = each_worker()
    READY.add(name)
    run_workers(entry, each)


def run_workers(entry, each: list[tuple]) -> None:
    """``entry(*arguments)`` for each worker's ``arguments`` in ``each``, in threads at once, this
    one and others of a pool: the kernels hold no lock of Python's (nogil), so each runs on a
    core of its own. Threads of
    Python's, not numba's parallel loop (prange): numba compiles such a loop into a function of
    its own, and a kernel's code is made again in each function that calls it, so that the
    loop made the largest part of a first use's compile twice. Returns when every worker has;
    the first worker's error, in order, is raised here (:func:`each_at_once`, which runs them).

    The other workers are kept off this thread's core while they run (:func:`submit_elsewhere`):
    Linux wakes a sleeping thread on the core of the thread that wakes it when it deems the
    other cores busy, as it may just after another program's threads ran on them, and then
    this thread and the worker share that core for the whole render while another idles."""
    each_at_once(lambda arguments: entry(*arguments), each, len(each))


def each_at_once(function: Callable, items: list, threads: int) -> None:
    """``function(item)`` for each of ``items``, ``threads`` of them at a time: a share in this
    thread, the others on the pool's threads off its core (:func:`submit_elsewhere`). An item
    whose call raises raises its error once all are done: the first item's in order, as calling
    them one by one would. Returns when every thread has, even on a Ctrl-C here: nothing of
    theirs runs on once it returns."""
    count = max(1, min(threads, len(items)))
    numbered = list(enumerate(items))
    shares = [numbered[k::count] for k in range(count)]
    errors: dict[int, Exception] = {}

    def call(share: list[tuple[int, object]]) -> None:
        for k, item in share:
            try:
                function(item)
            except Exception as error:  # noqa: BLE001 (raised below, in order)
                errors[k] = error

    submit = submit_elsewhere() if count > 1 else None
    others = [submit(call, share) for share in shares[1:]]
    try:
        call(shares[0])
    finally:  # no worker writes into a render's arrays once this returns
        for other in others:
            other.result()
    if errors:
        raise errors[min(errors)]


def submit_elsewhere() -> Callable[..., Future]:
    """A ``submit(function, *arguments)`` to the pool's threads (:func:`thread_pool`) whose
    calls run off the core this thread runs on now (:func:`elsewhere`), as a render's other
    workers do (:func:`run_workers`)."""
    away, pool = elsewhere(), thread_pool(os.getpid())
    return functools.partial(pool.submit, _away_from, away)


def elsewhere() -> set[int] | None:
    """The cores this thread may run on but the one it runs on now: where the other workers of
    a call run (:func:`_away_from`). None where that cannot be told, or leaves none."""
    try:
        allowed = os.sched_getaffinity(0)
    except (AttributeError, OSError):  # not Linux
        return None
    here = _current_core()
    if here is None or here not in allowed or len(allowed) < 2:
        return None
    return allowed - {here}


@functools.cache
def _sched_getcpu():
    """The C library's sched_getcpu, or None where it has none."""
    try:
        return ctypes.CDLL(None).sched_getcpu
    except (OSError, AttributeError):
        return None


def _current_core() -> int | None:
    """The core this thread runs on now, or None."""
    getcpu = _sched_getcpu()
    core = getcpu() if getcpu is not None else -1
    return core if core >= 0 else None


def _away_from(cores: set[int] | None, entry, *arguments) -> None:
    """``entry(*arguments)`` in this worker thread, which may run only on ``cores`` meanwhile
    (None: anywhere), and where it might before once it returns."""
    if cores is None:
        entry(*arguments)
        return
    try:
        before = os.sched_getaffinity(0)
        os.sched_setaffinity(0, cores)
    except OSError:  # a core taken away meanwhile: anywhere
        entry(*arguments)
        return
    try:
        entry(*arguments)
    finally:
        try:
            os.sched_setaffinity(0, before)
        except OSError:  # a core taken away meanwhile: the next call sets its own
            pass


@functools.cache
def thread_pool(process: int) -> ThreadPoolExecutor:
    """The threads of :func:`run_workers`' workers but the caller's, made once a ``process``
    (its id: a child forked from a process that made them has none of their threads): one
    fewer than numba's most threads, which numba.set_num_threads cannot exceed."""
    return ThreadPoolExecutor(max(1, numba.config.NUMBA_NUM_THREADS - 1), "raykit-worker")

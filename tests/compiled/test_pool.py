"""The threads a render's workers run on (raykit.engine.compiled.pool)."""

from __future__ import annotations

import os
import signal
import time
from dataclasses import replace

import numpy as np
import pytest

from conftest import SCENES
from raykit.engine import compiled
from raykit.engine.compiled import pool
from raykit.io.scene_json import load_scene

from .harness import two_threads


@two_threads()
def test_a_process_forked_after_a_render_renders_with_worker_threads_of_its_own():
    # a child forked from a process whose pool of workers' threads exists has none of those
    # threads: handed the parent's pool, it would wait for ever on work no thread runs
    scene = load_scene(SCENES / "classic.json")
    scene = replace(scene, camera=replace(scene.camera, width=64, height=48))
    prepared = compiled.prepare(scene)
    rgb = compiled.render.render(prepared)[0]  # two workers: the parent's pool is made
    assert pool.thread_pool.cache_info().currsize >= 1
    child = os.fork()
    if child == 0:  # pragma: no cover (the child's result is its exit status)
        try:
            os._exit(0 if np.array_equal(compiled.render.render(prepared)[0], rgb) else 1)
        finally:
            os._exit(2)
    deadline = time.monotonic() + 120
    while (status := os.waitpid(child, os.WNOHANG))[0] == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    if status[0] == 0:
        os.kill(child, signal.SIGKILL)
        os.waitpid(child, 0)
        pytest.fail("the forked child's render did not end within 120 s")
    assert os.waitstatus_to_exitcode(status[1]) == 0


def _cores(entry_saw: list):
    """An entry point stand-in that keeps the cores its thread may run on."""

    def entry(*arguments):
        entry_saw.append(os.sched_getaffinity(0))

    return entry


@pytest.mark.skipif(
    not hasattr(os, "sched_getaffinity") or len(os.sched_getaffinity(0)) < 2,
    reason="needs a thread that may run on two cores at least",
)
def test_the_other_workers_run_off_the_callers_core_and_anywhere_after():
    allowed = os.sched_getaffinity(0)
    assert pool._current_core() in allowed
    elsewhere = pool.elsewhere()  # all but the core this thread runs on as it asks
    assert elsewhere < allowed and len(elsewhere) == len(allowed) - 1
    away = allowed - {min(allowed)}  # as elsewhere() gives, for a caller on min(allowed)
    saw = []
    worker = pool.thread_pool(os.getpid())
    worker.submit(pool._away_from, away, _cores(saw)).result()
    assert saw == [away]  # kept off the caller's core while it ran
    assert worker.submit(os.sched_getaffinity, 0).result() == allowed  # anywhere again after
    saw.clear()
    pool.run_workers(_cores(saw), [()] * 2)  # the caller's and a worker's, in either order
    assert len(saw) == 2 and allowed in saw  # the caller's own, untouched
    assert len(min(saw, key=len)) == len(allowed) - 1  # the worker's: all but one core


def test_a_worker_that_cannot_be_kept_off_a_core_still_runs(monkeypatch):
    def refused(*arguments):
        raise OSError("not permitted")

    monkeypatch.setattr(os, "sched_setaffinity", refused)
    saw = []
    pool.thread_pool(os.getpid()).submit(pool._away_from, {0}, _cores(saw)).result()
    pool.thread_pool(os.getpid()).submit(pool._away_from, None, _cores(saw)).result()
    assert len(saw) == 2


@two_threads()
def test_each_at_once_calls_each_item_once_on_as_many_threads_as_asked():
    import threading

    calls = []
    pool.each_at_once(lambda item: calls.append((item, threading.get_ident())), list(range(6)), 2)
    assert sorted(item for item, _ in calls) == list(range(6))
    assert len({thread for _, thread in calls}) == 2
    calls.clear()
    pool.each_at_once(lambda item: calls.append((item, threading.get_ident())), list(range(6)), 1)
    assert calls == [(item, threading.get_ident()) for item in range(6)]  # here, in order


@two_threads()
def test_each_at_once_raises_the_first_items_error_in_order_once_all_are_done():
    done = []

    def call(item):
        if item in (1, 2):  # 1 in the other thread's share, 2 in this one's
            raise ValueError(f"item {item}")
        done.append(item)

    with pytest.raises(ValueError, match="item 1"):
        pool.each_at_once(call, list(range(4)), 2)
    assert sorted(done) == [0, 3]

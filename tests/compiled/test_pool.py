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

"""The workers' jobs (raykit.engine.compiled.jobs): each job taken by exactly one worker, and
the mean of a pixel's samples against raykit.engine.regions.Image.mean."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from raykit.engine import compiled
from raykit.engine.compiled import pool

from .harness import small_render, twin_test, two_threads


@numba.njit(nogil=True)
def _take_jobs(jobs, grain, taken, arrived, times):
    """One worker taking ``grain`` of ``jobs`` at a time from the counter ``taken``, by the loop
    every entry point runs (compiled.grain_taken), counting in its own row of ``times (workers,
    jobs)`` how often it took each (so that two workers' counts of one job never share a
    write)."""
    worker = compiled.take(arrived, 1)
    for _ in range(10**9):  # wait (a while at most) for the other workers: all take at once
        if compiled.take(arrived, 0) >= len(times):
            break
    work, mine = compiled.Work(jobs, grain, taken), np.zeros(2, np.int64)
    while compiled.grain_taken(work, mine):
        for j in range(mine[0], mine[1]):
            times[worker, j] += 1


def _times_taken(jobs, grain, workers):
    """How often each of ``workers`` workers, run as a render runs them (pool.run_workers), takes
    each of ``jobs``: ``(workers, jobs)``."""
    times = np.zeros((workers, jobs), dtype=np.int64)
    arguments = (np.arange(jobs), grain, np.zeros(1, np.int64), np.zeros(1, np.int64), times)
    pool.run_workers(_take_jobs, [arguments] * workers)
    return times


@two_threads()
@pytest.mark.parametrize("grain", [1, 7])
def test_cores_taking_jobs_from_one_counter_take_each_job_exactly_once(grain):
    # with a plain add for take, both workers took every job (measured)
    assert (_times_taken(1_000_000, grain, 2).sum(axis=0) == 1).all()


CHECKS = {
    "jobs.pixel_means": small_render("classic", samples=3),
}
test_the_twin_repeats_its_reference = twin_test("jobs", CHECKS)

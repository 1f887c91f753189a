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


@pytest.mark.parametrize("hits", [True, False])
@pytest.mark.parametrize("n", [1, 2, 3])
def test_a_job_casts_a_centre_ray_of_its_own_only_for_hits_kept_and_no_sample_at_the_centre(
    n, hits
):
    from raykit.camera import centre_sample, sample_offsets
    from raykit.engine.compiled.jobs import TileJob, job_points

    offsets, centre = sample_offsets(n), centre_sample(n)
    pixels = 4 * 2
    kept = pixels if hits else 0  # a film without index and t: the picture alone
    index, t = np.empty(kept, np.int64), np.empty(kept)
    centre_index = -1 if centre is None else centre
    film = compiled.Film(4, 2, np.zeros(0), np.zeros(0), offsets, centre_index,
                         np.empty((pixels, 3)), index, t)  # fmt: skip
    xy = np.full((2, pixels * (n * n + 1)), np.nan)
    rays = job_points(film, TileJob(0, 2, 0, 0, 4, 0), xy)
    extra = hits and centre is None
    assert rays == pixels * (n * n + extra)
    centres = xy[:, pixels * n * n :].T
    if extra:  # after all the samples, each pixel's centre, row by row
        assert centres.tolist() == [[x + 0.5, y + 0.5] for y in range(2) for x in range(4)]
    else:
        assert np.isnan(centres).all()

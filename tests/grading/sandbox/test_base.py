"""The run every kind of sandbox shares (raykit_grading.sandbox.base): its limits fitted to
what the container leaves."""

from __future__ import annotations

from raykit_grading.sandbox.confine import ContainerLimits


def test_a_childs_memory_is_cut_to_what_the_container_leaves_beside_the_grader_and_kernel():
    """L = G + K + M (raykit_grading.sandbox.budgets): at Gradescope's 768 MB the test may hold
    416 MB, the kernel 32 MB for it, the grader 320 MB; with no limit found, 2 GB."""
    from raykit_grading.sandbox.base import Limits, fit_to_container
    from raykit_grading.sandbox.budgets import GRADER_MEMORY, kernel_share

    limits = Limits(memory_bytes=2 * 1024**3)
    kernel = kernel_share(limits.open_files, limits.processes, limits.disk)
    assert kernel.total == 32 * 2**20 and kernel.pipes == 4 * 2**20  # 64 pipes of 16 pages
    gradescope = fit_to_container(limits, ContainerLimits(768 * 2**20, 0.5))
    assert gradescope.memory_bytes + GRADER_MEMORY + kernel.total == 768 * 2**20
    assert gradescope.memory_bytes == 416 * 2**20
    assert fit_to_container(limits, ContainerLimits(None, None)) == limits
    assert fit_to_container(limits, ContainerLimits(64 * 2**30, 4)) == limits

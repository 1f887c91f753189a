"""The billboard kernels (raykit.engine.compiled.billboards) against raykit.billboards: hits and
texels, bit for bit."""

from __future__ import annotations

from dataclasses import replace

import numba
import numpy as np
import pytest

from raykit.billboards import billboard_color_at, hit_billboard
from raykit.engine import compiled

from .harness import (
    RAYS,
    Texels,
    board_scene,
    exactly,
    random_rays,
    twin_test,
)


@numba.njit
def _boards(arrays, origins, directions, board):
    out = np.empty((len(origins), 3))
    for i in range(len(origins)):
        o, d = origins[i], directions[i]
        out[i] = compiled.hit_billboard(o[0], o[1], o[2], d[0], d[1], d[2], arrays, board)
    return out


@numba.njit
def _texels(arrays, board, alpha, beta):
    out = np.empty((len(alpha), 4))
    for i in range(len(alpha)):
        r, g, b, opaque = compiled.billboard_color_at(arrays, board, alpha[i], beta[i])
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = r, g, b, opaque
    return out


@pytest.mark.parametrize("where", ["random", "edge_on", "at_1e6", "on_the_plane"])
def test_billboard_kernel_repeats_hit_billboard_bit_for_bit(where):
    rng = np.random.default_rng(7)
    scene, board = board_scene(rng)
    count = RAYS if where == "random" else 20_000
    origins, directions = random_rays(rng, count, 4.0)
    if where == "random":  # aimed at and around the parallelogram
        alpha, beta = rng.uniform(-0.3, 1.3, size=(2, count, 1))
        toward = board.upper_left + alpha * board.a + beta * board.b - origins
        directions = toward / np.linalg.norm(toward, axis=1, keepdims=True)
    elif where == "edge_on":  # directions in the billboard's plane: parallel to it
        directions = np.cross(board.n, rng.normal(size=(count, 3)))
        directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    elif where == "at_1e6":
        scene, board = board_scene(np.random.default_rng(7))
        moved = lambda p: np.asarray(p) + 1e6  # noqa: E731
        board = replace(
            board,
            upper_left=moved(board.upper_left),
            lower_left=moved(board.lower_left),
            upper_right=moved(board.upper_right),
        )
        scene = replace(scene, billboards=(board,))
        origins = origins + 1e6
    elif where == "on_the_plane":  # rays that start on the billboard
        alpha, beta = rng.uniform(size=(2, count, 1))
        origins = board.upper_left + alpha * board.a + beta * board.b
    t, alpha, beta = hit_billboard(origins, directions, board)
    got = _boards(compiled.scene_arrays(scene), origins, directions, 0)
    exactly(got[:, 0], t)
    hit = np.isfinite(t)
    exactly(got[hit, 1], alpha[hit])
    exactly(got[hit, 2], beta[hit])
    if where == "random":
        assert 0.05 < hit.mean() < 0.9


def test_texel_kernel_repeats_the_nearest_texel_and_its_holes():
    rng = np.random.default_rng(9)
    rgba = rng.integers(0, 256, size=(7, 13, 4), dtype=np.uint8)
    scene, board = board_scene(rng, texture=Texels(rgba))
    alpha = np.concatenate([rng.uniform(size=RAYS), [0.0, 1.0, 0.5, 1 / 13, 12 / 13]])
    beta = np.concatenate([rng.uniform(size=RAYS), [0.0, 1.0, 1 / 7, 6 / 7, 0.5]])
    colors, opaque = billboard_color_at(board, alpha, beta)(np.arange(len(alpha)))
    got = _texels(compiled.scene_arrays(scene), 0, alpha, beta)
    exactly(got[:, :3], colors)
    assert np.array_equal(got[:, 3] == 1, opaque) and 0.3 < opaque.mean() < 0.7


def _hit_billboard(rng):
    scene, board = board_scene(rng)
    origins, _ = random_rays(rng, 20_000, 4.0)
    alpha, beta = rng.uniform(-0.3, 1.3, size=(2, len(origins), 1))
    toward = board.upper_left + alpha * board.a + beta * board.b - origins
    directions = toward / np.linalg.norm(toward, axis=1, keepdims=True)
    t, alpha, beta = hit_billboard(origins, directions, board)
    got = _boards(compiled.scene_arrays(scene), origins, directions, 0)
    hit = np.isfinite(t)
    exactly(got[:, 0], t)
    exactly(got[hit, 1:], np.stack([alpha[hit], beta[hit]], axis=1))


def _billboard_color_at(rng):
    scene, board = board_scene(
        rng, texture=Texels(rng.integers(0, 256, size=(5, 9, 4), dtype=np.uint8))
    )
    alpha, beta = rng.uniform(size=(2, 20_000))
    colors, opaque = billboard_color_at(board, alpha, beta)(np.arange(len(alpha)))
    got = _texels(compiled.scene_arrays(scene), 0, alpha, beta)
    exactly(got[:, :3], colors)
    assert np.array_equal(got[:, 3] == 1, opaque)


CHECKS = {
    "billboards.hit_billboard": _hit_billboard,
    "billboards.billboard_color_at": _billboard_color_at,
}
test_the_twin_repeats_its_reference = twin_test("billboards", CHECKS)

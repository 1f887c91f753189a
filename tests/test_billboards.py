import numpy as np
import pytest

from raykit.billboards import Billboard, hit_billboard, is_degenerate, texel_indices
from raykit.planes import hit_plane
from raykit.rays import MISS


def square(z=0.0) -> Billboard:
    """The unit square in the plane z, upper-left corner at (0, 1)."""
    return Billboard(
        upper_left=np.array([0.0, 1.0, z]),
        lower_left=np.array([0.0, 0.0, z]),
        upper_right=np.array([1.0, 1.0, z]),
        color=np.array([1.0, 1.0, 1.0]),
    )


def test_ray_plane_hit_distance_and_parallel_miss():
    o = np.array([[0.0, 0.0, 5.0], [0.0, 0.0, 5.0], [0.0, 0.0, 5.0]])
    d = np.array([[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    t = hit_plane(o, d, np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 1.0]))
    assert t[0] == pytest.approx(3.0)
    assert t[1] == MISS  # parallel
    assert t[2] == MISS  # behind


def test_alpha_beta_run_along_the_edges_from_the_upper_left_corner():
    o = np.array([[0.25, 0.9, 3.0], [0.75, 0.1, -3.0]])  # second ray from behind
    d = np.array([[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]])
    t, alpha, beta = hit_billboard(o, d, square())
    assert np.allclose(t, 3.0)
    assert np.allclose(alpha, [0.25, 0.75])
    assert np.allclose(beta, [0.1, 0.9])


def test_edges_are_inside_and_outside_is_a_miss():
    o = np.array([[0.0, 0.0, 1.0], [1.0, 1.0, 1.0], [1.0 + 1e-9, 0.5, 1.0], [0.5, -1e-9, 1.0]])
    d = np.tile([0.0, 0.0, -1.0], (4, 1))
    t, _, _ = hit_billboard(o, d, square())
    assert np.isfinite(t[:2]).all()
    assert (t[2:] == MISS).all()


def test_skewed_parallelogram_coordinates():
    b = Billboard(
        upper_left=np.array([0.0, 0.0, 0.0]),
        lower_left=np.array([1.0, -2.0, 0.0]),
        upper_right=np.array([3.0, 0.0, 0.0]),
        color=np.ones(3),
    )
    point = b.upper_left + 0.3 * b.a + 0.6 * b.b
    t, alpha, beta = hit_billboard(point[None] + [0, 0, 2.0], np.array([[0, 0, -1.0]]), b)
    assert (alpha[0], beta[0]) == pytest.approx((0.3, 0.6))


def test_texel_index_from_the_parameters_clamps_the_far_edge():
    row, col = texel_indices(np.array([0.0, 0.49, 0.5, 1.0]), np.array([0.0, 0.2, 0.99, 1.0]), 4, 2)
    assert col.tolist() == [0, 1, 2, 3]
    assert row.tolist() == [0, 0, 1, 1]


def test_degenerate_corners_are_detected():
    assert is_degenerate(np.array([1.0, 0, 0]), np.array([2.0, 0, 0]))
    assert is_degenerate(np.array([0.0, 0, 0]), np.array([0.0, 1, 0]))
    assert not is_degenerate(np.array([1e-6, 0, 0]), np.array([0.0, 1e-6, 0]))

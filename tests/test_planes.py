import numpy as np
import pytest

from raykit.planes import hit_plane, normal_from_points, plane_side


def test_points_in_front_on_and_behind_the_plane():
    a, n = np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 2.0])
    p = np.array([[3.0, -1.0, 1.5], [5.0, 7.0, 1.0], [0.0, 0.0, -4.0]])
    assert plane_side(p, a, n).tolist() == [1, 0, -1]


def test_side_is_the_slides_comparison_of_p_dot_n_with_a_dot_n():
    rng = np.random.default_rng(19)
    p = rng.uniform(-10, 10, (1000, 3))
    a, n = rng.uniform(-1, 1, 3), rng.normal(size=3)
    side = plane_side(p, a, n)
    assert side.shape == (1000,)
    assert side.dtype.kind == "i"
    assert ((side == 1) == (p @ n > a @ n)).all()
    assert ((side == -1) == (p @ n < a @ n)).all()


def test_turning_the_normal_round_swaps_front_and_back():
    rng = np.random.default_rng(19)
    p, a, n = rng.normal(size=(50, 3)), rng.normal(size=3), rng.normal(size=3)
    assert (plane_side(p, a, -n) == -plane_side(p, a, n)).all()


def test_sides_work_in_two_dimensions_for_the_line_scan_world():
    a, n = np.zeros(2), np.array([0.0, 1.0])
    assert plane_side(np.array([[4.0, 1.0], [4.0, -1.0], [-2.0, 0.0]]), a, n).tolist() == [1, -1, 0]


def test_normal_from_three_points_is_not_normalized():
    """(p - a) × (q - a): perpendicular to both edges, twice the triangle's area long."""
    a, p, q = np.array([1.0, 1.0, 1.0]), np.array([4.0, 1.0, 1.0]), np.array([1.0, 3.0, 1.0])
    n = normal_from_points(a, p, q)
    assert n.tolist() == [0.0, 0.0, 6.0]  # length 6 = 2 x (3 x 2 / 2), not 1
    assert normal_from_points(a, q, p).tolist() == [0.0, 0.0, -6.0]  # swapped: turned round


def test_normal_from_points_gives_the_plane_they_lie_on():
    rng = np.random.default_rng(19)
    a, p, q = rng.normal(size=(3, 20, 3))
    n = normal_from_points(a, p, q)
    for point in (a, p, q):
        assert np.einsum("ij,ij->i", point - a, n) == pytest.approx(np.zeros(20), abs=1e-12)
    # and a ray aimed at q from off the plane hits it at q, whatever n's length
    o = a + 3 * n
    t = hit_plane(o[:1], q[:1] - o[:1], a[0], n[0])
    assert t[0] == pytest.approx(1.0)


def test_points_on_one_line_give_a_zero_normal():
    a, p = np.zeros(3), np.array([1.0, 2.0, 3.0])
    assert not normal_from_points(a, p, 2 * p).any()


def test_ray_plane_hit_is_where_f_of_p_of_t_is_zero_and_parallel_or_behind_is_a_miss():
    # the slide's derivation: substitute p(t) = o + t·d into f(p) = (p - a)·n and solve for t
    rng = np.random.default_rng(20)
    o, d = rng.normal(size=(200, 3)), rng.normal(size=(200, 3))
    a, n = rng.normal(size=3), rng.normal(size=3)
    t = hit_plane(o, d, a, n)
    met = np.isfinite(t)
    assert 50 < met.sum() < 150  # about half the rays point toward the plane
    f = (o[met] + t[met, None] * d[met] - a) @ n
    assert np.allclose(f, 0, atol=1e-9)
    assert (t[met] > 0).all()
    # the others would meet it at t <= 0, behind their origin
    assert (((a - o[~met]) @ n) / (d[~met] @ n) <= 0).all()
    parallel = np.cross(n, rng.normal(size=3))  # d·n = 0
    assert hit_plane(o[:1], parallel[None], a, n)[0] == np.inf

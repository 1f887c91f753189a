"""The t > 0 rule of raykit.rays: a ray never hits the surface it starts on.

Each test starts rays exactly on a surface (t = 0 is a root) and would fail if hits at t = 0
counted, as the slides' t ≥ 0 would allow.
"""

import numpy as np
import pytest

from raykit.billboards import Billboard, hit_billboard
from raykit.linescan.camera import LineCamera, line_rays
from raykit.linescan.objects import Ball
from raykit.linescan.scan import trace
from raykit.linescan.scene import LineScene
from raykit.planes import hit_plane
from raykit.rays import MISS, nearest_positive
from raykit.spheres import hit_sphere, hit_sphere_textbook


def test_nearest_positive_skips_a_root_at_exactly_zero():
    t = nearest_positive(np.array([0.0, -0.0, 0.0]), np.array([3.0, 2.0, -1.0]))
    assert t.tolist() == [3.0, 2.0, MISS]


@pytest.mark.parametrize("hit", [hit_sphere, hit_sphere_textbook])
def test_ray_leaving_a_sphere_from_its_surface_misses_it(hit):
    rng = np.random.default_rng(19)
    normals = rng.normal(size=(200, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    on_surface = 2.0 * normals  # exactly representable roots: radius 2, centre 0, unit normals
    origins = np.array([[0.0, 0.0, 2.0], [2.0, 0.0, 0.0], [0.0, -2.0, 0.0]])
    outward = origins / 2.0
    assert (hit(origins, outward, np.zeros(3), 2.0) == MISS).all()
    # and rays from random surface points along their outward normal: no hit at (near) t = 0
    t = hit(on_surface, normals, np.zeros(3), 2.0)
    assert not (t == 0).any()


def test_ray_entering_a_sphere_from_its_surface_hits_the_far_side_not_its_start():
    origins = np.array([[0.0, 0.0, 2.0], [2.0, 0.0, 0.0]])
    inward = -origins / 2.0
    assert hit_sphere(origins, inward, np.zeros(3), 2.0) == pytest.approx([4.0, 4.0])


def test_ray_starting_on_a_plane_does_not_hit_it():
    origins = np.array([[1.0, 2.0, 0.0], [-3.0, 0.5, 0.0]])
    directions = np.array([[0.0, 0.3, 1.0], [0.2, 0.0, -1.0]])  # leaving either side
    t = hit_plane(origins, directions, np.zeros(3), np.array([0.0, 0.0, 1.0]))
    assert (t == MISS).all()


def test_ray_starting_on_a_billboard_does_not_hit_it():
    board = Billboard(
        upper_left=np.array([-1.0, 1.0, 0.0]),
        lower_left=np.array([-1.0, -1.0, 0.0]),
        upper_right=np.array([1.0, 1.0, 0.0]),
        color=np.ones(3),
    )
    origins = np.array([[0.0, 0.0, 0.0], [0.5, -0.5, 0.0]])
    directions = np.array([[0.0, 0.0, 1.0], [0.1, 0.2, -1.0]])
    t, _, _ = hit_billboard(origins, directions, board)
    assert (t == MISS).all()


def test_line_scan_ray_starting_on_a_ball_sees_past_it():
    """In the 2D world too: an eye on a ball's rim, looking away from it, sees the background."""
    camera = LineCamera(e=np.array([0.0, 1.0]), w=np.array([0.0, 1.0]), fov_angle=60, pixels=5)
    ball = Ball(center=np.zeros(2), radius=1.0, color=np.array([1.0, 0.0, 0.0]))
    hits = trace(LineScene(camera, balls=(ball,)), *line_rays(camera))
    assert (hits.index == -1).all()


def test_dot_with_a_unit_vector_is_the_length_of_the_projection():
    """The slide's dot product as a projection: r·u is how far r reaches along unit u, and
    r - (r·u)u is perpendicular to u."""
    from raykit.rays import dot, normalize

    rng = np.random.default_rng(19)
    r, u = rng.normal(size=(50, 3)), normalize(rng.normal(size=(50, 3)))
    along = dot(r, u)
    assert along == pytest.approx(np.linalg.norm(r, axis=1) * np.cos(_angle(r, u)))
    assert dot(r - along[:, None] * u, u) == pytest.approx(np.zeros(50), abs=1e-12)


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    cos = np.einsum("ij,ij->i", a, b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.arccos(np.clip(cos, -1, 1))


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_cross_is_numpys_cross_bit_for_bit_in_its_dtype_and_broadcasts(dtype):
    """raykit.rays.cross makes np.cross's products and differences: the same bits, for single
    vectors, rows, and a vector against rows."""
    from raykit.rays import cross

    rng = np.random.default_rng(23)
    a, b = (
        (rng.normal(size=(40, 3)) * 10.0 ** rng.integers(-6, 7, (40, 1))).astype(dtype)
        for _ in "ab"
    )
    for x, y in ((a, b), (a[0], b[0]), (a, b[0]), (a[0], b)):
        made = cross(x, y)
        assert made.dtype == np.cross(x, y).dtype == dtype
        assert made.tobytes() == np.cross(x, y).tobytes()
    assert cross([1, 0, 0], [0, 1, 0]).tolist() == [0, 0, 1]  # x × y = z: right-handed

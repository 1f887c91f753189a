import numpy as np
import pytest

from exact import exact_sphere_hit
from raykit.rays import MISS, normalize
from raykit.spheres import hit_sphere, hit_sphere_textbook, sphere_f


def rays(origins, directions):
    return np.atleast_2d(np.asarray(origins, float)), np.atleast_2d(np.asarray(directions, float))


def test_ray_through_centre_hits_at_distance_minus_radius():
    o, d = rays([0, 0, 10], [0, 0, -1])
    assert hit_sphere(o, d, np.zeros(3), 2.0)[0] == pytest.approx(8.0)


def test_ray_from_inside_hits_the_far_side():
    o, d = rays([0, 0, 0.5], [0, 0, -1])
    assert hit_sphere(o, d, np.zeros(3), 2.0)[0] == pytest.approx(2.5)


def test_sphere_behind_the_ray_is_missed():
    o, d = rays([0, 0, 10], [0, 0, 1])
    assert hit_sphere(o, d, np.zeros(3), 2.0)[0] == MISS


def test_ray_starting_on_the_surface_and_leaving_misses():
    o, d = rays([0, 0, 2], [0, 0, 1])
    assert hit_sphere(o, d, np.zeros(3), 2.0)[0] == MISS


def test_negative_discriminant_misses_and_tangent_grazes():
    o, d = rays([[3, 0, 10], [2, 0, 10]], [[0, 0, -1], [0, 0, -1]])
    t = hit_sphere(o, d, np.zeros(3), 2.0)
    assert t[0] == MISS
    assert t[1] == pytest.approx(10.0)


def test_unnormalised_direction_gives_parameter_not_distance():
    o, d = rays([0, 0, 10], [0, 0, -4])
    assert hit_sphere(o, d, np.zeros(3), 2.0)[0] == pytest.approx(2.0)


def test_works_in_two_dimensions_as_ray_circle():
    o, d = rays([0, 10], [0, -1])
    assert hit_sphere(o, d, np.zeros(2), 3.0)[0] == pytest.approx(7.0)


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_tiny_far_sphere_stable_form_classifies_every_ray_textbook_does_not(dtype):
    """A 1e-3 sphere at 1e5: b'^2 and a*c' are ~1e10 and agree to 16 digits, so the textbook
    discriminant is rounding noise near the silhouette. The stable one matches exact math on
    the very rays it is given, in float64 and in float32."""
    rng = np.random.default_rng(7)
    center, radius = np.array([0.0, 0.0, -1e5], dtype), dtype(1e-3)
    n = 400
    aim = center + np.column_stack(
        [rng.uniform(-1.5e-3, 1.5e-3, n), rng.uniform(-1.5e-3, 1.5e-3, n), np.zeros(n)]
    )
    origins, directions = np.zeros((n, 3), dtype), normalize(aim).astype(dtype)
    exact = np.array(
        [exact_sphere_hit(origins[i], directions[i], center, radius) for i in range(n)]
    )
    stable = np.isfinite(hit_sphere(origins, directions, center, radius))
    textbook = np.isfinite(hit_sphere_textbook(origins, directions, center, radius))
    assert 0.2 * n < exact.sum() < 0.8 * n  # the sample straddles the silhouette
    assert np.array_equal(stable, exact)
    assert (textbook != exact).sum() > 0.1 * n


def test_textbook_formula_takes_the_lower_positive_root_in_the_slide_letters():
    """o = (0, 0, 10), d = (0, 0, -1), c = 0, R = 2: A = 1, B = -20, C = 96, D = 16,
    t = (20 ± 4)/2 = 8 or 12, and the lower one is the hit."""
    o, d = rays([0, 0, 10], [0, 0, -1])
    assert hit_sphere_textbook(o, d, np.zeros(3), 2.0)[0] == 8.0


def test_stable_and_textbook_forms_agree_on_ordinary_rays():
    """D = 4Δ and (-B ± √D)/2A = (-b' ± √Δ)/A with only powers of two between them: the forms
    differ only in how they compute Δ and the cancelling root, which ordinary rays barely feel."""
    rng = np.random.default_rng(19)
    origins = rng.uniform(-5, 5, (500, 3)) + np.array([0, 0, 10])
    directions = normalize(rng.uniform(-1, 1, (500, 3)) - origins / 10)
    stable = hit_sphere(origins, directions, np.zeros(3), 2.0)
    textbook = hit_sphere_textbook(origins, directions, np.zeros(3), 2.0)
    assert (np.isfinite(stable) == np.isfinite(textbook)).all()
    assert np.isfinite(stable).sum() > 20
    assert stable[np.isfinite(stable)] == pytest.approx(textbook[np.isfinite(textbook)], rel=1e-9)


def test_sphere_f_is_negative_inside_zero_on_and_positive_outside():
    c = np.array([1.0, 2.0, 3.0])
    points = np.array([c, c + [0, 0, 2.0], c + [0, 3.0, 0], c + [1.0, 0, 0]])
    assert sphere_f(points, c, 2.0).tolist() == [-4.0, 0.0, 5.0, -3.0]
    # a ray's hit is where f(p(t)) = 0
    o, d = rays([1, 2, 13], [0, 0, -1])
    t_hit = hit_sphere(o, d, c, 2.0)
    assert sphere_f(o + t_hit[:, None] * d, c, 2.0)[0] == pytest.approx(0.0, abs=1e-12)

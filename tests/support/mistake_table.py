"""Where each classic mistake of tests/support/mistaken_submissions.py must be named: the tests
of the function it is made in (and of its callers that have array tests), and one render or scan
that shows it; a camera mistake made in _in_plane, in every visible render too."""

NAMED_IN = {
    "rows_flipped": ["3.2", "3.6"],
    "u_v_swapped": ["3.1", "3.2", "3.6"],
    "u_negated": ["3.2", "3.6"],
    "fov_horizontal": ["3.2", "3.6", "3.7", "4.8", "4.9"],
    "aspect_ignored": ["3.2", "3.6", "3.7", "4.8", "4.9"],
    "pixel_corners": ["3.2", "3.6", "3.7", "3.8", "4.8", "4.9"],
    "pixel_x_corners": ["1.1", "1.2", "1.3", "1.6", "1.7"],
    "slide_second_formula": ["3.2", "3.6"],
    "degrees_as_radians": ["3.2", "3.6", "3.7", "4.8", "4.9"],
    "far_root": ["2.3", "4.8"],
    "textbook_discriminant": ["2.5"],
    "texture_rows_flipped": ["3.5", "3.7"],
    "behind_the_eye": ["2.1", "2.3", "3.9", "3.10"],
    "t_zero_accepted": ["2.2"],
    "normal_not_unit": ["4.1", "4.8"],
    "light_reversed": ["4.2", "4.3", "4.8"],
    "no_offset": ["4.7", "4.11"],
    "reflect_sign": ["4.6", "4.10"],
    "half_vector_not_unit": ["4.5", "4.8"],
    "area_light_as_point": ["5.6", "5.16", "5.20"],
    "aperture_as_radius": ["5.9", "5.10", "5.17", "5.20"],
    "not_jittered": ["5.3", "5.4", "5.16", "5.17"],
    "jitter_missing": ["5.3", "5.4", "5.16", "5.17"],
    "basis_not_orthonormal": ["5.11", "5.12", "5.13", "5.18"],
    "time_per_pixel": ["5.14", "5.19"],
}


def _says(key: str) -> str:
    """What the grader says of mistake ``key`` (``when ...``), as the tests look for it."""
    from raykit_grading.assignment.mistakes import MISTAKES

    return next(m.says for m in MISTAKES if m.key == key)

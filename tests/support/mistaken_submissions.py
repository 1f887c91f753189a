"""Submissions with one classic mistake each: the solution with one line written wrong, the way
students get it wrong, in the one function where they make it: always a function the student
writes (the release's stubs; a wrong image plane size is computed in _in_plane, which the
solution has read from the given Camera.plane_size). Each entry: the mistake's key in
raykit_grading.assignment.mistakes, then (file, the right line, the wrong line) edits applied to a
copy of raykit/."""

from __future__ import annotations

import shutil
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]

EDITS = {
    "rows_flipped": [
        (
            "camera.py",
            "t = Hp / 2 - np.asarray(y, dtype=float) * (Hp / camera.height)",
            "t = -Hp / 2 + np.asarray(y, dtype=float) * (Hp / camera.height)",
        )
    ],
    "u_v_swapped": [("camera.py", "    return u, v, w\n", "    return v, u, w\n")],
    "u_negated": [
        (
            "camera.py",
            "return s[:, None] * u + t[:, None] * v",
            "return -s[:, None] * u + t[:, None] * v",
        )
    ],
    "fov_horizontal": [
        (
            "camera.py",
            "    Wp, Hp = camera.plane_size\n    s = -Wp",
            "    Wp = 2 * camera.d * math.tan(math.radians(camera.fov_angle) / 2)\n"
            "    Hp = Wp * camera.height / camera.width\n    s = -Wp",
        )
    ],
    "aspect_ignored": [
        (
            "camera.py",
            "    Wp, Hp = camera.plane_size\n    s = -Wp",
            "    Hp = 2 * camera.d * math.tan(math.radians(camera.fov_angle) / 2)\n"
            "    Wp = Hp\n    s = -Wp",
        )
    ],
    "pixel_corners": [
        (
            "camera.py",
            "s = -Wp / 2 + np.asarray(x, dtype=float) * (Wp / camera.width)",
            "s = -Wp / 2 + (np.asarray(x, dtype=float) - 0.5) * (Wp / camera.width)",
        ),
        (
            "camera.py",
            "t = Hp / 2 - np.asarray(y, dtype=float) * (Hp / camera.height)",
            "t = Hp / 2 - (np.asarray(y, dtype=float) - 0.5) * (Hp / camera.height)",
        ),
    ],
    "pixel_x_corners": [
        (
            "linescan/camera.py",
            "return -1.0 + (i + (k + 0.5) / samples) * (2.0 / pixels)",
            "return -1.0 + (i + k / samples) * (2.0 / pixels)",
        )
    ],
    "textbook_discriminant": [
        (
            "spheres.py",
            "discriminant = A * (radius * radius - dot(closest, closest))  # Δ = D/4",
            "discriminant = b * b - A * C  # Δ = D/4, the textbook's b'² - AC",
        )
    ],
    "t_zero_accepted": [
        (
            "planes.py",
            "np.where((d_dot_n != 0) & (t > 0), t, MISS)",
            "np.where((d_dot_n != 0) & (t >= 0), t, MISS)",
        )
    ],
    "slide_second_formula": [
        (
            "camera.py",
            "s = -Wp / 2 + np.asarray(x, dtype=float) * (Wp / camera.width)",
            "s = -Wp / 2 + (np.asarray(x, dtype=float) - 0.5) * (Wp / (camera.width - 1))",
        ),
        (
            "camera.py",
            "t = Hp / 2 - np.asarray(y, dtype=float) * (Hp / camera.height)",
            "t = Hp / 2 - (np.asarray(y, dtype=float) - 0.5) * (Hp / (camera.height - 1))",
        ),
    ],
    "degrees_as_radians": [
        (
            "camera.py",
            "    Wp, Hp = camera.plane_size\n    s = -Wp",
            "    Hp = 2 * camera.d * math.tan(camera.fov_angle / 2)\n"
            "    Wp = Hp * camera.width / camera.height\n    s = -Wp",
        )
    ],
    "far_root": [
        (
            "spheres.py",
            "nearest_positive(t0, t1), MISS)",
            "np.where(np.fmax(t0, t1) > 0, np.fmax(t0, t1), MISS), MISS)",
        )
    ],
    "texture_rows_flipped": [
        (
            "billboards.py",
            "row = np.minimum(np.floor(beta * height), height - 1)",
            "row = height - 1 - np.minimum(np.floor(beta * height), height - 1)",
        )
    ],
    "behind_the_eye": [
        ("spheres.py", "nearest_positive(t0, t1), MISS)", "np.fmin(t0, t1), MISS)"),
        (
            "planes.py",
            "np.where((d_dot_n != 0) & (t > 0), t, MISS)",
            "np.where(d_dot_n != 0, t, MISS)",
        ),
    ],
    "normal_not_unit": [
        ("spheres.py", "return (points - center) / radius", "return points - center")
    ],
    "light_reversed": [
        (
            "lights.py",
            "normalize(-np.asarray(light.direction, float))",
            "normalize(np.asarray(light.direction, float))",
        ),
        (
            "lights.py",
            "to_light = np.asarray(light.position) - points",
            "to_light = points - np.asarray(light.position)",
        ),
    ],
    "no_offset": [
        (
            "shadows.py",
            "hits = cast(surface.start(l), l, distance)",
            "hits = cast(surface.points, l, distance)",
        )
    ],
    "reflect_sign": [
        (
            "mirrors.py",
            "return d - 2.0 * dot(d, n)[:, None] * n",
            "return d + 2.0 * dot(d, n)[:, None] * n",
        )
    ],
    "half_vector_not_unit": [
        ("shading.py", "h = normalize(l + v)\n    return", "h = l + v\n    return")
    ],
    "area_light_as_point": [
        (
            "lights.py",
            "point_on_parallelogram(light.corner, light.edge1, light.edge2, uniforms), light.color",
            "np.broadcast_to(light.corner + 0.5 * light.edge1 + 0.5 * light.edge2, "
            "(len(uniforms), 3)), light.color",
        )
    ],
    "aperture_as_radius": [("sampling.py", "radius = aperture / 2.0", "radius = aperture")],
    "not_jittered": [
        (
            "sampling.py",
            "return (grid + np.asarray(uniforms, dtype=float)) / n",
            "return np.asarray(uniforms, dtype=float)",
        )
    ],
    "jitter_missing": [
        (
            "sampling.py",
            "return (grid + np.asarray(uniforms, dtype=float)) / n",
            "return (grid + 0.5) / n",
        )
    ],
    "basis_not_orthonormal": [
        ("sampling.py", "u = normalize(np.cross(t, w))", "u = np.cross(t, w)")
    ],
    "time_per_pixel": [
        (
            "sampling.py",
            "return shutter_open + np.asarray(uniforms, dtype=float) * (shutter_close - "
            "shutter_open)",
            "uniforms = np.asarray(uniforms, dtype=float)\n"
            "    first = shutter_open + uniforms[:, :1] * (shutter_close - shutter_open)\n"
            "    return np.repeat(first, uniforms.shape[1], axis=1)",
        )
    ],
}

# Stage 5's functions written right but another way, as a student may: other orders of the
# same operations (so other roundings), numpy's own cos and sin, the focal point formed away
# from the eye. Each entry replaces a function's solution, the lines between its hint and
# END SOLUTION; a correct submission like this one must score in full.
REWRITTEN = {
    ("sampling.py", "point_in_pixel"): """\
    u = np.asarray(uniforms, dtype=float)
    return u[:, 0] + np.asarray(cols), u[:, 1] + np.asarray(rows)
""",
    ("sampling.py", "jittered_point"): """\
    cells = np.asarray(cells)
    u = np.asarray(uniforms, dtype=float)
    i, j, step = cells % n, cells // n, 1.0 / n
    return np.column_stack([i * step + u[:, 0] * step, j * step + u[:, 1] * step])
""",
    ("sampling.py", "jittered_set"): """\
    return np.array([jittered_point(np.array([k]), n, uniforms[k : k + 1])[0]
                     for k in range(n * n)])
""",
    ("sampling.py", "point_on_parallelogram"): """\
    u = np.asarray(uniforms, dtype=float)
    return np.asarray(corner) + (u[:, :1] * np.asarray(edge1) + u[:, 1:] * np.asarray(edge2))
""",
    ("sampling.py", "point_on_disk"): """\
    u = np.asarray(uniforms, dtype=float)
    a, b = 2 * u[:, 0] - 1, 2 * u[:, 1] - 1
    wide = np.abs(a) > np.abs(b)
    r = np.where(wide, a, b)
    with np.errstate(invalid="ignore", divide="ignore"):
        phi = np.where(wide, np.pi / 4 * (b / a), np.pi / 2 - np.pi / 4 * (a / b))
    phi = np.where(r == 0, 0.0, phi)
    return np.column_stack([r * np.cos(phi), r * np.sin(phi)])
""",
    ("sampling.py", "point_on_lens"): """\
    disk = point_on_disk(uniforms)
    half = aperture * disk / 2
    return np.asarray(eye) + half[:, :1] * np.asarray(u) + half[:, 1:] * np.asarray(v)
""",
    ("sampling.py", "basis_around"): """\
    r = np.asarray(r, dtype=float)
    w = r / np.sqrt((r * r).sum(axis=1))[:, None]
    t = w.copy()
    t[np.arange(len(w)), np.argmin(np.abs(w), axis=1)] = 1
    u = np.cross(t, w)
    u = u / np.sqrt((u * u).sum(axis=1))[:, None]
    return u, np.cross(w, u), w
""",
    ("sampling.py", "perturbed_direction"): """\
    u, v, _ = basis_around(r)
    xi = np.asarray(uniforms, dtype=float)
    moved = np.asarray(r) + ((xi[:, :1] - 0.5) * a) * u + ((xi[:, 1:] - 0.5) * a) * v
    return moved / np.sqrt((moved * moved).sum(axis=1))[:, None]
""",
    ("lights.py", "sampled"): """\
    c, e1, e2 = light.corner, light.edge1, light.edge2
    xi = np.asarray(uniforms, dtype=float)
    return PointLight(c + xi[:, :1] * e1 + xi[:, 1:] * e2, light.color)
""",
    ("mirrors.py", "glossy_reflect"): """\
    r = d - 2 * (d * n).sum(axis=1)[:, None] * n
    a = np.asarray(a, dtype=float)
    moved = np.where((a > 0)[:, None], perturbed_direction(r, a[:, None], uniforms), r)
    leaves = (moved * n).sum(axis=1) * (d * n).sum(axis=1) < 0
    return moved, (a == 0) | leaves
""",
    ("sampling.py", "shutter_times"): """\
    xi = np.asarray(uniforms, dtype=float)
    return (1 - xi) * shutter_open + xi * shutter_close
""",
    ("spheres.py", "center_at"): """\
    return np.asarray(center) + np.outer(times, velocity)
""",
    ("camera.py", "thin_lens_rays"): """\
    u, v, w = camera.frame
    eye = np.asarray(camera.eye, dtype=float)
    P = eye - camera.d * w + _in_plane(camera, x, y)
    s = eye + (camera.focus / camera.d) * (P - eye)
    r = point_on_lens(eye, u, v, camera.aperture, uniforms)
    return r, normalize(s - r)
""",
}


def rewrite(folder: Path, name: str, function: str, body: str) -> None:
    """Replace ``function``'s solution in ``folder/raykit/name`` by ``body``."""
    path = folder / "raykit" / name
    text = path.read_text()
    start = text.index(f"def {function}(")
    begin = text.index("    # BEGIN SOLUTION\n", start)
    end = text.index("    # END SOLUTION\n", begin)
    path.write_text(text[:begin] + body + text[end + len("    # END SOLUTION\n") :])


def make_rewritten(folder: Path) -> Path:
    """A submission whose stage-5 functions are :data:`REWRITTEN`: right, another way."""
    make_submission(folder)
    for (name, function), body in REWRITTEN.items():
        rewrite(folder, name, function, body)
    return folder


def make_submission(folder: Path, key: str | None = None) -> Path:
    """A submission folder holding raykit/ with the mistake ``key`` made (None: the solution)."""
    shutil.copytree(
        REPO / "raykit", folder / "raykit", ignore=shutil.ignore_patterns("__pycache__")
    )
    for name, right, wrong in EDITS.get(key, []) if key else []:
        path = folder / "raykit" / name
        text = path.read_text()
        assert text.count(right) == 1, f"{key}: {right!r} is not once in {name}"
        path.write_text(text.replace(right, wrong))
    return folder

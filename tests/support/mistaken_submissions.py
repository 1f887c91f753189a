"""Submissions with one classic mistake each: the solution with one line written wrong, the way
students get it wrong, in the one function where they make it: always a function the student
writes (the release's stubs; a wrong image plane size is computed in _in_plane, which the
solution has read from the given Camera.plane_size). Each entry: the mistake's key in
raykit_grading.mistakes, then (file, the right line, the wrong line) edits applied to a copy of
raykit/."""

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
}


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

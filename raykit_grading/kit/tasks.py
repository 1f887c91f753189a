"""The tasks a grading test can run: each one function of the submission's raykit on the test's
inputs, arrays out.

The same :data:`TASKS` run in the grader with the reference raykit, to make the expected
results, and in the sandbox's child (:mod:`raykit_grading.inside.child`) with the submission's; so a
task is written once and means the same on both sides. This file imports only numpy and raykit,
and only inside the tasks, so it imports whichever raykit comes first on the path: in the
child, the submission's. The child loads it from its work folder by path; the starter kit
carries it as ``_grading/tasks.py`` for ``check.py``.
"""

from __future__ import annotations


def _line_camera(spec: dict):
    import numpy as np

    from raykit.linescan.camera import LineCamera

    return LineCamera(
        np.array(spec["e"], float),
        np.array(spec["w"], float),
        spec["fov_angle"],
        spec["pixels"],
        spec.get("projection", "perspective"),
        spec.get("width", 2.0),
    )


def _camera(spec: dict):
    import numpy as np

    from raykit.camera import Camera

    return Camera(
        np.array(spec["eye"], float),
        np.array(spec["lookat"], float),
        np.array(spec["up"], float),
        spec["fov_angle"],
        spec["width"],
        spec["height"],
        spec.get("projection", "perspective"),
        **{k: spec[k] for k in ("aperture", "focus_distance") if k in spec},
    )


def task_probe(spec, arrays):
    """The grader's preflight: the sandbox's Python imports numpy and Pillow."""
    import numpy as np
    import PIL.Image  # noqa: F401

    return {"ok": np.ones(1)}


# the modules of raykit the tasks import: a submission none of whose tests can run without them
IMPORTED = (
    "raykit", "raykit.billboards", "raykit.camera", "raykit.io.linescan_json",
    "raykit.io.scene_json", "raykit.lights", "raykit.linescan.camera", "raykit.linescan.objects",
    "raykit.linescan.scan", "raykit.mirrors", "raykit.planes", "raykit.render",
    "raykit.sampling", "raykit.shading", "raykit.shadows", "raykit.spheres", "raykit.surfaces",
)  # fmt: skip


def task_imports(spec, arrays):
    """Before any test: which of raykit's modules the tasks use import (1) or not (0), and
    for each that does not, one printed line ``import failed: <the error's last line> (in
    raykit/<file>, line <n>)``, the last place in the submission's files its traceback names.
    If the package itself or every one of them fails, nothing can be tested: the first error
    is raised, for the grader to say once."""
    import importlib
    import traceback

    import numpy as np

    errors = {}
    for name in IMPORTED:
        try:
            importlib.import_module(name)
        except Exception as exc:  # noqa: BLE001 - the student's error, said by the grader
            if name == "raykit":
                raise
            errors[name] = exc
            print(f"import failed: {_where_it_failed(exc, traceback)}")
    if len(errors) == len(IMPORTED) - 1:
        raise next(iter(errors.values()))
    return {"imports": np.array([name not in errors for name in IMPORTED], dtype=float)}


def _where_it_failed(exc: BaseException, traceback) -> str:
    """``SyntaxError: invalid syntax (in raykit/shading.py, line 12)``: the error's last line
    and the last place in the submission (``.../submission/raykit/...``) it names."""
    said = traceback.format_exception_only(type(exc), exc)[-1].strip()
    places = [(frame.filename, frame.lineno) for frame in traceback.extract_tb(exc.__traceback__)]
    if isinstance(exc, SyntaxError) and exc.filename:
        places.append((exc.filename, exc.lineno))
    theirs = [(f.split("/submission/", 1)[1], n) for f, n in places if "/submission/" in f]
    return f"{said} (in {theirs[-1][0]}, line {theirs[-1][1]})" if theirs else said


def task_pixel_x(spec, arrays):
    from raykit.linescan.camera import pixel_x

    return {"x": pixel_x(spec["pixels"], spec.get("samples", 1))}


def task_line_rays(spec, arrays):
    from raykit.linescan.camera import line_rays

    origins, directions = line_rays(_line_camera(spec["camera"]), spec.get("samples", 1))
    return {"origins": origins, "directions": directions}


def task_hit_segment(spec, arrays):
    import numpy as np

    from raykit.linescan.objects import Billboard, hit_segment

    board = Billboard(
        np.array(spec["start"], float), np.array(spec["end"], float), color=np.ones(3)
    )
    t, s = hit_segment(arrays["origins"], arrays["directions"], board)
    return {"t": t, "s": np.where(np.isfinite(t), s, np.nan)}


def task_hit_plane(spec, arrays):
    from raykit.planes import hit_plane

    return {"t": hit_plane(arrays["origins"], arrays["directions"], arrays["a"], arrays["n"])}


def task_plane_side(spec, arrays):
    from raykit.planes import plane_side

    return {"side": plane_side(arrays["p"], arrays["a"], arrays["n"])}


def task_normal_from_points(spec, arrays):
    from raykit.planes import normal_from_points

    return {"n": normal_from_points(arrays["a"], arrays["p"], arrays["q"])}


def task_hit_sphere(spec, arrays):
    from raykit.spheres import hit_sphere

    return {
        "t": hit_sphere(
            arrays["origins"], arrays["directions"], arrays["center"], float(spec["radius"])
        )
    }


def task_camera_frame(spec, arrays):
    import numpy as np

    from raykit.camera import camera_frame

    u, v, w = camera_frame(*(np.array(spec[k], float) for k in ("eye", "lookat", "up")))
    return {"u": u, "v": v, "w": w}


def task_rays_through(spec, arrays):
    from raykit.camera import rays_through

    origins, directions = rays_through(_camera(spec["camera"]), arrays["x"], arrays["y"])
    return {"origins": origins, "directions": directions}


def task_in_plane(spec, arrays):
    from raykit.camera import _in_plane

    return {"in_plane": _in_plane(_camera(spec["camera"]), arrays["x"], arrays["y"])}


def task_hit_billboard(spec, arrays):
    import numpy as np

    from raykit.billboards import Billboard, hit_billboard

    board = Billboard(
        *(np.array(spec[k], float) for k in ("upper_left", "lower_left", "upper_right")),
        color=np.ones(3),
    )
    t, alpha, beta = hit_billboard(arrays["origins"], arrays["directions"], board)
    hit = np.isfinite(t)
    return {"t": t, "alpha": np.where(hit, alpha, np.nan), "beta": np.where(hit, beta, np.nan)}


def task_texel_indices(spec, arrays):
    from raykit.billboards import texel_indices

    row, column = texel_indices(arrays["alpha"], arrays["beta"], spec["width"], spec["height"])
    return {"row": row, "column": column}


def task_sphere_normals(spec, arrays):
    from raykit.spheres import sphere_normals

    return {"n": sphere_normals(arrays["points"], arrays["center"], float(spec["radius"]))}


def task_toward_light(spec, arrays):
    import numpy as np

    from raykit.lights import DirectionalLight, PointLight, toward_light

    place = np.array(spec.get("direction", spec.get("position")), float)
    light = (DirectionalLight if "direction" in spec else PointLight)(place, np.ones(3))
    l, distance = toward_light(light, arrays["points"])
    return {"l": l, "distance": distance}


def task_lambert(spec, arrays):
    from raykit.shading import lambert

    return {"L": lambert(arrays["kd"], arrays["intensity"], arrays["n"], arrays["l"])}


def task_blinn_phong(spec, arrays):
    from raykit.shading import blinn_phong

    return {
        "L": blinn_phong(
            arrays["ks"], arrays["intensity"], arrays["n"], arrays["l"], arrays["v"], arrays["p"]
        )
    }


def task_reflect(spec, arrays):
    from raykit.mirrors import reflect

    return {"r": reflect(arrays["d"], arrays["n"])}


def task_in_shadow(spec, arrays):
    from raykit.io.scene_json import scene_from_dict
    from raykit.render import secondary_caster
    from raykit.shadows import in_shadow
    from raykit.surfaces import SurfacePoints

    scene = scene_from_dict(spec["scene"])
    surface = SurfacePoints(arrays["points"], arrays["normals"], arrays["error"])
    blocked = in_shadow(secondary_caster(scene), surface, arrays["l"], arrays["distance"])
    return {"blocked": blocked.astype(float)}


def task_point_in_pixel(spec, arrays):
    from raykit.sampling import point_in_pixel

    x, y = point_in_pixel(arrays["rows"], arrays["cols"], arrays["uniforms"])
    return {"x": x, "y": y}


def task_random_set(spec, arrays):
    from raykit.sampling import random_set

    return {"samples": random_set(arrays["uniforms"])}


def task_jittered_point(spec, arrays):
    from raykit.sampling import jittered_point

    return {"points": jittered_point(arrays["cells"], spec["n"], arrays["uniforms"])}


def task_jittered_set(spec, arrays):
    from raykit.sampling import jittered_set

    return {"samples": jittered_set(spec["n"], arrays["uniforms"])}


def task_point_on_parallelogram(spec, arrays):
    from raykit.sampling import point_on_parallelogram

    corner, edge1, edge2 = (arrays[k] for k in ("corner", "edge1", "edge2"))
    return {"points": point_on_parallelogram(corner, edge1, edge2, arrays["uniforms"])}


def task_sampled(spec, arrays):
    from raykit.lights import AreaLight, sampled

    light = AreaLight(arrays["corner"], arrays["edge1"], arrays["edge2"], arrays["color"])
    point = sampled(light, arrays["uniforms"])
    # broadcast: the colour is the light's, one (3,) for all its points
    return {"position": point.position, "color": point.color}


def task_point_on_disk(spec, arrays):
    from raykit.sampling import point_on_disk

    return {"points": point_on_disk(arrays["uniforms"])}


def task_point_on_lens(spec, arrays):
    from raykit.sampling import point_on_lens

    eye, u, v = (arrays[k] for k in ("eye", "u", "v"))
    return {"points": point_on_lens(eye, u, v, float(spec["aperture"]), arrays["uniforms"])}


def task_thin_lens_rays(spec, arrays):
    from raykit.camera import thin_lens_rays

    camera = _camera(spec["camera"])
    origins, directions = thin_lens_rays(camera, arrays["x"], arrays["y"], arrays["uniforms"])
    return {"origins": origins, "directions": directions}


def task_basis_around(spec, arrays):
    from raykit.sampling import basis_around

    u, v, w = basis_around(arrays["r"])
    return {"u": u, "v": v, "w": w}


def task_perturbed_direction(spec, arrays):
    from raykit.sampling import perturbed_direction

    return {"r": perturbed_direction(arrays["r"], float(spec["a"]), arrays["uniforms"])}


def task_glossy_reflect(spec, arrays):
    from raykit.mirrors import glossy_reflect

    r, above = glossy_reflect(arrays["d"], arrays["n"], arrays["a"], arrays["uniforms"])
    return {"r": r, "above": above.astype(float)}


def task_shutter_times(spec, arrays):
    from raykit.sampling import shutter_times

    return {"times": shutter_times(spec["open"], spec["close"], arrays["uniforms"])}


def task_center_at(spec, arrays):
    from raykit.spheres import center_at

    return {"centers": center_at(arrays["center"], arrays["velocity"], arrays["times"])}


def task_render(spec, arrays):
    from raykit.io.scene_json import scene_from_dict
    from raykit.render import render

    scene = scene_from_dict(spec["scene"], folder=spec["folder"])
    # every object against every ray: skipping assumes right answers (t > 0), and a student's
    # wrong ones must show in the image
    return {"rgb": render(scene, samples=spec.get("samples", 1), skip_hidden=False).rgb}


def task_scan(spec, arrays):
    from raykit.io.linescan_json import line_scene_from_dict
    from raykit.linescan.scan import scan

    return {"rgb": scan(line_scene_from_dict(spec["scene"], folder=spec["folder"])).colors[None]}


def task_sweep(spec, arrays):
    from raykit.io.linescan_json import line_scene_from_dict
    from raykit.linescan.scan import sweep

    scene = line_scene_from_dict(spec["scene"], folder=spec["folder"])
    return {"rgb": sweep(scene, spec.get("scans")).image}


TASKS = {name[len("task_") :]: f for name, f in dict(globals()).items() if name.startswith("task_")}

"""The loader's columns of plain spheres (raykit.spheres.SphereTable) stand for the tuple of
Spheres they hold: the same spheres, the same arrays for the engine, the same pictures."""

from dataclasses import replace

import numpy as np
import pytest

from raykit.engine.arrays import SceneArrays
from raykit.io.scene_json import scene_from_dict
from raykit.materials import PLAIN
from raykit.render import render
from raykit.spheres import Sphere, SphereTable


def _plain_scene_dict(count: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    return {
        "camera": {
            "eye": [0, 0, 6], "lookat": [0, 0, 0], "up": [0, 1, 0],
            "fov_angle": 50, "width": 48, "height": 36,
        },
        "background": [0.1, 0.2, 0.3],
        "spheres": [
            {
                "center": rng.uniform(-2, 2, 3).tolist(),
                "radius": float(rng.uniform(0.1, 0.6)),
                "color": rng.uniform(0, 1, 3).tolist(),
            }
            for _ in range(count)
        ],
        "billboards": [
            {
                "upper_left": [-3, 2, -3], "upper_right": [3, 2, -3], "lower_left": [-3, -2, -3],
                "color": [0.5, 0.5, 0.5],
            }
        ],
    }  # fmt: skip


def _as_tuple(scene):
    """The same scene with its spheres as a tuple of Sphere objects, as before the table."""
    return replace(scene, spheres=tuple(scene.spheres))


def test_loaded_plain_spheres_are_a_table_that_reads_as_their_tuple():
    data = _plain_scene_dict(5, seed=1)
    spheres = scene_from_dict(data).spheres
    assert isinstance(spheres, SphereTable) and len(spheres) == 5
    for i, given in enumerate(data["spheres"]):
        sphere = spheres[i]
        assert isinstance(sphere, Sphere) and (sphere.name, sphere.material) == (None, PLAIN)
        assert np.array_equal(sphere.center, given["center"]) and sphere.radius == given["radius"]
        assert np.array_equal(sphere.color, given["color"])
    assert np.array_equal(spheres[-1].center, data["spheres"][-1]["center"])
    assert [s.radius for s in spheres] == [s["radius"] for s in data["spheres"]]
    assert isinstance(spheres[1:3], SphereTable) and len(spheres[1:3]) == 2
    assert spheres[1:3][0].radius == spheres[1].radius
    both = spheres + (spheres[0],)
    assert isinstance(both, tuple) and len(both) == 6
    assert spheres == scene_from_dict(data).spheres and spheres != spheres[1:]
    with pytest.raises(IndexError):
        spheres[5]
    with pytest.raises(ValueError, match="read-only"):
        spheres[0].center[0] = 9.0  # a scene is data: its spheres cannot be changed in place


def test_the_engine_takes_the_tables_columns_as_the_tuple_would_give_them():
    scene = scene_from_dict(_plain_scene_dict(30, seed=2))
    table, listed = SceneArrays.of(scene), SceneArrays.of(_as_tuple(scene))
    for name in ("centers", "radii", "sphere_colors"):
        assert np.array_equal(getattr(table, name), getattr(listed, name))
    for a, b in zip(table.boxes, listed.boxes, strict=True):
        assert np.array_equal(a, b)
    for name in ("diffuse", "has_diffuse", "specular", "shininess", "mirror"):
        got, expected = getattr(scene.materials, name), getattr(_as_tuple(scene).materials, name)
        assert got.dtype == expected.dtype and np.array_equal(got, expected)
    assert scene.object_count == len(scene.objects) == 31


@pytest.mark.parametrize("lit", [False, True])
def test_a_scene_renders_the_same_bits_from_the_table_and_from_the_tuple(lit):
    data = _plain_scene_dict(40, seed=3)
    if lit:
        data["lights"] = [{"type": "point", "position": [2, 3, 4]}]
        data["ambient"] = [0.1, 0.1, 0.1]
    scene = scene_from_dict(data)
    table, listed = (render(s, 2, engine="numpy") for s in (scene, _as_tuple(scene)))
    for name in ("rgb", "object_index", "t"):
        assert np.array_equal(getattr(table, name), getattr(listed, name))


@pytest.mark.parametrize("collector_on", [True, False])
def test_a_scene_file_is_parsed_and_dropped_with_the_cycle_collector_off_then_as_before(
    tmp_path, monkeypatch, collector_on
):
    # the collector looked over the parsed file's containers again and again as they were made
    import gc
    import json

    from raykit.io import fields
    from raykit.io.scene_json import load_scene

    path = tmp_path / "scene.json"
    path.write_text(json.dumps(_plain_scene_dict(20, seed=4)))
    seen = []
    parse = json.loads
    monkeypatch.setattr(
        fields.json, "loads", lambda text: seen.append(gc.isenabled()) or parse(text)
    )
    (gc.enable if collector_on else gc.disable)()
    try:
        scene = load_scene(path)
        assert gc.isenabled() is collector_on  # as it was, once the file is read
    finally:
        gc.enable()
    assert seen == [False] and len(scene.spheres) == 20

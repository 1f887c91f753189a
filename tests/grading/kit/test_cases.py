"""A practice test on disk (raykit_grading.kit.cases): a case folder read back as it was
written, its spec's folder made a path inside the case's folder."""

from __future__ import annotations

import json

import numpy as np

from raykit_grading.kit.cases import located, read_case


def test_a_case_is_read_back_as_written_with_its_spec_folder_inside_the_case(tmp_path):
    rng = np.random.default_rng(58)
    inputs = {"origins": rng.normal(size=(5, 3)), "pixels": np.arange(7, dtype=np.int32)}
    expected = {"t": rng.uniform(0, 9, 5), "hit": rng.random(5) < 0.5}
    order = {"task": "scan", "kind": "image", "name": "1.6 one scan", "points": 2,
             "spec": {"scene": {"camera": {"pixels": 7}}, "folder": "scene"}}  # fmt: skip
    (tmp_path / "task.json").write_text(json.dumps(order))
    np.savez(tmp_path / "inputs.npz", **inputs)
    np.savez(tmp_path / "expected.npz", **expected)

    read, arrays, want = read_case(tmp_path)

    assert read["spec"] == {"scene": {"camera": {"pixels": 7}}, "folder": str(tmp_path / "scene")}
    assert {k: v for k, v in read.items() if k != "spec"} == {
        k: v for k, v in order.items() if k != "spec"
    }
    for got, wrote in ((arrays, inputs), (want, expected)):
        assert got.keys() == wrote.keys()
        for key in wrote:
            assert got[key].dtype == wrote[key].dtype and np.array_equal(got[key], wrote[key])


def test_a_spec_without_a_folder_is_kept_and_no_spec_is_changed_in_place(tmp_path):
    plain = {"pixels": 12, "samples": 3}
    assert located(plain, tmp_path) == {"pixels": 12, "samples": 3}
    with_folder = {"scene": {}, "folder": "scene"}
    assert located(with_folder, str(tmp_path))["folder"] == str(tmp_path / "scene")
    assert with_folder == {"scene": {}, "folder": "scene"}  # the caller's spec, as it was

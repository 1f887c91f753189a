"""Shared helpers: small scenes built in code, and the repository's folders."""

from __future__ import annotations

import copy
import json
import os
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
SCENES = REPO / "scenes"
AS_ROOT = os.geteuid() == 0  # the sandbox's uids, the chroot, Docker's emulation need root


def scene_dict(**overrides) -> dict:
    """A minimal valid v1 scene (one sphere at the origin, seen from +z), with overrides."""
    scene = {
        "camera": {
            "eye": [0, 0, 5],
            "lookat": [0, 0, 0],
            "up": [0, 1, 0],
            "fov_angle": 45,
            "width": 32,
            "height": 24,
        },
        "spheres": [{"center": [0, 0, 0], "radius": 1, "color": [1, 0, 0]}],
    }
    scene.update(copy.deepcopy(overrides))
    return scene


def set_field(path: str, value):
    """A scene mutation that sets the field at a dotted path (list indices as numbers)."""

    def mutate(scene: dict) -> None:
        *parents, last = [int(k) if k.isdigit() else k for k in path.split(".")]
        node = scene
        for key in parents:
            node = node[key]
        node[last] = value

    return mutate


def delete_field(path: str):
    """A scene mutation that deletes the field at a dotted path."""

    def mutate(scene: dict) -> None:
        *parents, last = [int(k) if k.isdigit() else k for k in path.split(".")]
        node = scene
        for key in parents:
            node = node[key]
        del node[last]

    return mutate


def shifted_scene(scene, offset):
    """A copy of a scene, as data (dict) or as a :class:`raykit.scene.Scene`, with every point
    (eye, lookat, centres, corners, point lights) moved by ``offset (3,)``: the same picture,
    far from the origin."""
    offset = np.asarray(offset, float)
    if not isinstance(scene, dict):
        from dataclasses import replace

        from raykit.lights import PointLight

        def moved(thing, *fields):
            return replace(thing, **{f: getattr(thing, f) + offset for f in fields})

        corners = ("upper_left", "lower_left", "upper_right")
        return replace(
            scene,
            camera=moved(scene.camera, "eye", "lookat"),
            spheres=tuple(moved(sphere, "center") for sphere in scene.spheres),
            billboards=tuple(moved(board, *corners) for board in scene.billboards),
            lights=tuple(
                moved(light, "position") if isinstance(light, PointLight) else light
                for light in scene.lights
            ),
        )
    scene = json.loads(json.dumps(scene))

    def move(point):
        return (np.asarray(point) + offset).tolist()

    camera = scene["camera"]
    camera["eye"], camera["lookat"] = move(camera["eye"]), move(camera["lookat"])
    for sphere in scene.get("spheres", []):
        sphere["center"] = move(sphere["center"])
    for board in scene.get("billboards", []):
        for key in ("upper_left", "lower_left", "upper_right"):
            board[key] = move(board[key])
    for light in scene.get("lights", []):
        if "position" in light:
            light["position"] = move(light["position"])
    return scene


def write_texture(folder: Path, name: str, rgba) -> str:
    """Save texels ``(H, W, 4)`` as an RGBA PNG in ``folder``; returns its name."""
    from PIL import Image

    Image.fromarray(np.asarray(rgba, np.uint8), "RGBA").save(folder / name)
    return name


def random_scene(rng: np.random.Generator, texture: str) -> dict:
    """A random small v1 scene: odd sizes, any fov, off-axis up, either projection, sometimes
    the camera inside a sphere, billboards flat or with ``texture`` (holes and all)."""
    width, height = (int(x) for x in rng.integers(7, 41, size=2))
    eye = rng.uniform(-6, 6, 3)
    lookat = rng.uniform(-2, 2, 3)
    scene = {
        "camera": {
            "eye": eye.tolist(),
            "lookat": lookat.tolist(),
            "up": rng.normal(size=3).tolist(),
            "fov_angle": float(rng.uniform(5, 170)),
            "width": width,
            "height": height,
            "projection": str(rng.choice(["perspective", "orthographic"])),
        },
        "spheres": [
            {
                "center": rng.uniform(-4, 4, 3).tolist(),
                "radius": float(rng.uniform(0.2, 2)),
                "color": [1, 0, 0],
            }
            for _ in range(int(rng.integers(0, 6)))
        ],
        "billboards": [],
    }
    if rng.random() < 0.3:  # sometimes the camera is inside a sphere
        scene["spheres"].append(
            {
                "center": (eye + rng.uniform(-0.5, 0.5, 3)).tolist(),
                "radius": 1.5,
                "color": [0, 1, 0],
            }
        )
    for _ in range(int(rng.integers(0, 5))):
        ul = rng.uniform(-4, 4, 3)
        board = {
            "upper_left": ul.tolist(),
            "lower_left": (ul + rng.uniform(-3, 3, 3)).tolist(),
            "upper_right": (ul + rng.uniform(-3, 3, 3)).tolist(),
        }
        board.update({"image": texture} if rng.random() < 0.5 else {"color": [0, 0, 1]})
        scene["billboards"].append(board)
    return scene


@pytest.fixture
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def child_python() -> str:
    """The Python graded submissions run on: this one. The sandbox mounts it (numpy and Pillow
    only) wherever it lives, as root under /root too (raykit_grading.sandbox.isolation)."""
    import sys

    return sys.executable


@pytest.fixture(scope="session")
def grader_python() -> str:
    """A Python like the zip's ``setup.sh`` makes (only the grader's pinned requirements),
    that every uid can run (tests/support/grader_python.py); skips saying why where it cannot
    be made."""
    from grader_python import grader_python as make

    python, why = make()
    if python is None:
        pytest.skip(why)
    return python


@pytest.fixture(scope="session")
def release(tmp_path_factory) -> Path:
    """The student release, built once per session; a test that changes it changes a copy."""
    from raykit_grading.assignment.release import build_release

    out = tmp_path_factory.mktemp("release") / "student"
    build_release(out)
    return out


@pytest.fixture(scope="session")
def solution(tmp_path_factory) -> Path:
    """The course's solution, submitted as a student would (tests/support/mistaken_submissions)."""
    from mistaken_submissions import make_submission

    return make_submission(tmp_path_factory.mktemp("solution"))


# the tests the class is graded on: a ray-sphere array test, the camera frame, a render: 7 points
CLASS_TESTS = ["2.3", "3.1", "3.6"]


@pytest.fixture(scope="session")
def graded_class(tmp_path_factory, release):
    """A class graded end to end by ``batch``, once: honest, half-done, mistaken, non-importing
    and zipped submissions beside a Gradescope export, graded on :data:`CLASS_TESTS` by the
    documented command: (its output folder, the run). Its users, grading/test_batch.py and
    grading/test_report.py, share one worker (conftest.py at the top), so it is made once."""
    import shutil
    import subprocess
    import sys
    import zipfile

    from gradescope_export import make_export

    from mistaken_submissions import make_submission

    root = tmp_path_factory.mktemp("class")
    students = root / "submissions"
    make_submission(students / "ada")  # honest
    hal = make_submission(students / "hal")  # half-done: spheres.py as the kit gives it
    shutil.copy(release / "raykit/spheres.py", hal / "raykit/spheres.py")
    make_submission(students / "mo", "u_v_swapped")
    make_submission(students / "flo", "rows_flipped")
    bo = make_submission(students / "bo")  # does not import
    with open(bo / "raykit/__init__.py", "a") as module:
        module.write("\ndef broken(:\n")
    cy = make_submission(students / "cy")  # one module of stage 4 does not import
    with open(cy / "raykit/mirrors.py", "a") as module:
        module.write("\ndef broken(:\n")
    erin = make_submission(root / "erin")  # zipped, beside the folders
    with zipfile.ZipFile(students / "erin.zip", "w") as archive:
        for file in sorted((erin / "raykit").rglob("*.py")):
            archive.write(file, file.relative_to(erin).as_posix())
    (students / "notes.txt").write_text("grade these by Friday")
    make_export(
        students / "gradescope-export.zip",
        {
            "submission_241730101": make_submission(root / "grace"),
            "submission_241730202": make_submission(root / "pair", "u_v_swapped"),
        },
    )
    out = root / "graded"
    run = subprocess.run(
        [sys.executable, "-m", "raykit_grading", "batch", str(students), "-o", str(out),
         "--only", *CLASS_TESTS, "--jobs", "2"],
        capture_output=True, text=True, cwd=root, timeout=900,
    )  # fmt: skip
    return out, run


def pytest_collection_modifyitems(config, items):
    """Grading runs submissions in bubblewrap sandboxes; where bwrap is not installed, say so
    and skip those tests (but never in CI, which installs it: there they must run)."""
    import os
    import shutil

    if shutil.which("bwrap") or os.environ.get("CI"):
        return
    skip = pytest.mark.skip(
        reason="grading needs bubblewrap (apt-get install bubblewrap) to sandbox submissions"
    )
    for item in items:
        if "child_python" in getattr(item, "fixturenames", ()) or "hostile" in item.nodeid:
            item.add_marker(skip)


def pytest_sessionstart(session):
    session.config.stash[_SEED_IN_CLONE] = (REPO / "grading-seed").exists()


def pytest_sessionfinish(session, exitstatus):
    """A test that runs a grading command with no seed option in the clone makes the clone an
    assignment folder (raykit_grading.assignment.seeds): every test runs its commands in folders of
    its own, and the run fails if the clone gained a seed."""
    seed = REPO / "grading-seed"
    if seed.exists() and not session.config.stash.get(_SEED_IN_CLONE, True):
        seed.unlink()
        print(f"\nerror: a test made {seed} (ran a grading command in the clone): removed it")
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


_SEED_IN_CLONE = pytest.StashKey[bool]()

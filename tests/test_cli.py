import json
import os
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest
from PIL import Image

from conftest import SCENES
from raykit.cli import main
from raykit.io.scene_json import load_scene
from raykit.render import render


def test_render_writes_the_png_and_says_what_it_wrote(tmp_path, capsys):
    out = tmp_path / "classic.png"
    assert main(["render", str(SCENES / "classic.json"), "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"wrote {out} (640x480, 1x1 samples per pixel, numpy engine) in ")
    assert said.rstrip().endswith(" s")
    image = np.asarray(Image.open(out))
    assert image.shape == (480, 640, 3)


def test_width_option_renders_the_same_view_in_that_many_pixels_of_the_same_shape(tmp_path):
    out = tmp_path / "o.png"
    assert main(["render", str(SCENES / "classic.json"), "-o", str(out), "--width", "160"]) == 0
    scene = load_scene(SCENES / "classic.json")
    smaller = replace(scene, camera=replace(scene.camera, width=160, height=120))
    from raykit.io.images import quantize

    assert np.array_equal(np.asarray(Image.open(out)), quantize(render(smaller).rgb))


def test_samples_option_averages_n_by_n_rays(tmp_path, capsys):
    out = tmp_path / "o.png"
    assert main(["render", str(SCENES / "cutouts.json"), "-o", str(out), "--samples", "2"]) == 0
    expected = render(load_scene(SCENES / "cutouts.json"), samples=2).rgb
    from raykit.io.images import quantize

    assert np.array_equal(np.asarray(Image.open(out)), quantize(expected))


def test_bad_samples_and_missing_output_are_usage_errors(tmp_path):
    for args in (["--samples", "0"], ["--samples", "x"], []):
        command = [sys.executable, "-m", "raykit", "render", str(SCENES / "classic.json")]
        command += args + (["-o", str(tmp_path / "o.png")] if args else [])
        run = subprocess.run(command, capture_output=True, text=True)
        assert run.returncode == 2
        assert "Traceback" not in run.stderr
    assert not (tmp_path / "o.png").exists()


def test_unwritable_output_folder_is_one_line_exit_2(tmp_path, capsys):
    out = tmp_path / "no" / "such" / "folder.png"
    assert main(["render", str(SCENES / "classic.json"), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("raykit: error:")


def test_help_lists_the_render_command():
    run = subprocess.run([sys.executable, "-m", "raykit", "--help"], capture_output=True, text=True)
    assert run.returncode == 0 and "render" in run.stdout


def test_version_prints_the_installed_version():
    from importlib.metadata import version

    run = subprocess.run(
        [sys.executable, "-m", "raykit", "--version"], capture_output=True, text=True
    )
    assert run.returncode == 0
    assert run.stdout == f"raykit {version('raykit')}\n"


def test_abbreviated_options_are_refused_not_guessed(tmp_path):
    # "--sample 4" once silently meant "--samples 4"; every parser has allow_abbrev=False
    for command in (
        ["render", str(SCENES / "classic.json"), "-o", str(tmp_path / "o.png"), "--sample", "4"],
        ["render", str(SCENES / "classic.json"), "--out", str(tmp_path / "o.png")],
        ["diagram", str(SCENES / "classic.json"), "-o", str(tmp_path / "o.png"), "--vi", "top"],
        ["bench", "--qu"],
    ):
        run = subprocess.run(
            [sys.executable, "-m", "raykit", *command], capture_output=True, text=True
        )
        assert run.returncode == 2, command
        assert "unrecognized arguments" in run.stderr or "required" in run.stderr, command
        assert "Traceback" not in run.stderr
    assert not (tmp_path / "o.png").exists()


def _refuse_to_work(*args, **kwargs):
    raise AssertionError("the output path should have been refused before any work")


# every command that writes a file, with the output path spliced in for {out}
WRITERS = {
    "render": ["render", str(SCENES / "classic.json"), "-o", "{out}"],
    "scan": ["scan", str(SCENES / "linescan/slide.json"), "-o", "{out}"],
    "scan --diagram": [
        "scan",
        str(SCENES / "linescan/slide.json"),
        "-o",
        "{ok}",
        "--diagram",
        "{out}",
    ],
    "sweep": ["sweep", str(SCENES / "linescan/conveyor.json"), "-o", "{out}"],
    "sweep --diagram": [
        "sweep",
        str(SCENES / "linescan/conveyor.json"),
        "-o",
        "{ok}",
        "--diagram",
        "{out}",
    ],
    "diagram": ["diagram", str(SCENES / "classic.json"), "-o", "{out}", "--view", "top"],
}


def _bad_output(tmp_path, monkeypatch, capsys, command, out):
    """Run ``command`` with ``out`` as the checked path; nothing may be rendered or drawn."""
    import raykit.diagrams.rays
    import raykit.linescan.scan
    import raykit.render

    for module, name in (
        (raykit.render, "render"),
        (raykit.linescan.scan, "scan"),
        (raykit.linescan.scan, "sweep"),
        (raykit.diagrams.rays, "ray_diagram"),
    ):
        monkeypatch.setattr(module, name, _refuse_to_work)
    ok = tmp_path / "fine.png"
    argv = [a.format(out=out, ok=ok) for a in WRITERS[command]]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert not ok.exists()
    return err


@pytest.mark.parametrize("command", WRITERS)
def test_missing_output_folder_is_refused_before_rendering(tmp_path, monkeypatch, capsys, command):
    out = tmp_path / "out" / "classic.png"
    err = _bad_output(tmp_path, monkeypatch, capsys, command, out)
    assert err == f"raykit: error: {out}: folder {tmp_path / 'out'} does not exist\n"


@pytest.mark.parametrize("command", WRITERS)
def test_unknown_output_suffix_is_refused_before_rendering(tmp_path, monkeypatch, capsys, command):
    out = tmp_path / "classic.pnx"
    err = _bad_output(tmp_path, monkeypatch, capsys, command, out)
    assert err.startswith(f"raykit: error: {out}: ") and "'.pnx'" in err and "use .png" in err


@pytest.mark.parametrize("command", WRITERS)
def test_output_folder_that_is_a_file_is_refused_before_rendering(
    tmp_path, monkeypatch, capsys, command
):
    (tmp_path / "notes.txt").write_text("a file, not a folder")
    out = tmp_path / "notes.txt" / "classic.png"
    err = _bad_output(tmp_path, monkeypatch, capsys, command, out)
    assert err == f"raykit: error: {out}: {tmp_path / 'notes.txt'} is a file, not a folder\n"


@pytest.mark.skipif(
    hasattr(os, "geteuid") and os.geteuid() == 0,
    reason="root may write into a read-only folder; the folder-is-a-file test covers the check",
)
@pytest.mark.parametrize("command", WRITERS)
def test_unwritable_output_folder_is_refused_before_rendering(
    tmp_path, monkeypatch, capsys, command
):
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        err = _bad_output(tmp_path, monkeypatch, capsys, command, folder / "classic.png")
    finally:
        folder.chmod(0o755)
    assert err == f"raykit: error: {folder / 'classic.png'}: folder {folder} is not writable\n"


def test_a_line_scan_scene_given_to_render_says_to_use_scan(tmp_path, capsys):
    scene = SCENES / "linescan/slide.json"
    assert main(["render", str(scene), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith(f"raykit: error: {scene}: a 2D line-scan scene")
    assert "use raykit scan" in err and "unknown" not in err
    assert not (tmp_path / "o.png").exists()


def test_a_3d_scene_given_to_scan_says_to_use_render(tmp_path, capsys):
    scene = SCENES / "classic.json"
    assert main(["scan", str(scene), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"raykit: error: {scene}: a 3D scene") and "use raykit render" in err


def test_a_3d_scene_with_a_typo_still_gets_the_field_error(tmp_path, capsys):
    # "balls" alone would look like a line-scan scene; the camera's eye says it is 3D
    scene = json.loads((SCENES / "classic.json").read_text())
    scene["balls"] = scene.pop("spheres")
    path = tmp_path / "typo.json"
    path.write_text(json.dumps(scene))
    assert main(["render", str(path), "-o", str(tmp_path / "o.png")]) == 2
    err = capsys.readouterr().err
    assert "balls" in err and "line-scan" not in err


def test_the_engine_option_offers_exactly_the_engines_render_knows():
    # the parser keeps its own copy, so that `raykit --help` imports no numpy
    from raykit.cli import build_parser
    from raykit.engine.choice import ENGINES

    parser = build_parser()
    for command in ("render", "bench"):
        sub = next(a for a in parser._subparsers._group_actions[0].choices[command]._actions
                   if a.dest == "engine")  # fmt: skip
        assert tuple(sub.choices) == ENGINES


@pytest.mark.parametrize("during", ["the render", "the write"])
def test_ctrl_c_says_so_in_one_line_exits_130_and_leaves_no_file_half_written(
    during, tmp_path, monkeypatch, capsys
):
    import PIL.Image

    import raykit.render

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    def interrupted_half_way(image, stream, *args, **kwargs):
        stream.write(b"\x89PNG\r\n\x1a\n")  # the start of the file, then Ctrl-C
        raise KeyboardInterrupt

    if during == "the render":
        monkeypatch.setattr(raykit.render, "render", interrupted)
    else:
        monkeypatch.setattr(PIL.Image.Image, "save", interrupted_half_way)
    out = tmp_path / "o.png"
    assert main(["render", str(SCENES / "cutouts.json"), "-o", str(out)]) == 130
    assert capsys.readouterr().err == "raykit: interrupted\n"
    assert list(tmp_path.iterdir()) == []

import subprocess
import sys

import numpy as np
from PIL import Image

from conftest import SCENES
from raykit.cli import main
from raykit.render import render
from raykit.scene import load_scene


def test_render_writes_the_png_and_says_what_it_wrote(tmp_path, capsys):
    out = tmp_path / "classic.png"
    assert main(["render", str(SCENES / "classic.json"), "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"wrote {out} (640x480, 1x1 samples per pixel) in ")
    assert said.rstrip().endswith(" s")
    image = np.asarray(Image.open(out))
    assert image.shape == (480, 640, 3)


def test_samples_option_averages_n_by_n_rays(tmp_path, capsys):
    out = tmp_path / "o.png"
    assert main(["render", str(SCENES / "cutouts.json"), "-o", str(out), "--samples", "2"]) == 0
    expected = render(load_scene(SCENES / "cutouts.json"), samples=2).rgb
    from raykit.images import quantize

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

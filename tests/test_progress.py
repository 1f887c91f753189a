"""Progress bars: on a terminal's stderr only, never in captured output; warnings above them;
the render reports every pixel once; notebooks/execute.py refuses to run without ipywidgets."""

import importlib.util
import io
import subprocess
import sys
import warnings

import pytest

from conftest import REPO, SCENES
from raykit.io.progress import progress_bar, wanted
from raykit.io.scene_json import load_scene
from raykit.render import render


class Terminal(io.StringIO):
    """A stream that says it is a terminal, as a user's stderr is."""

    def isatty(self):
        return True


def test_no_bar_where_nobody_watches():
    for stream in (io.StringIO(), None):
        with progress_bar(10, "work", stream=stream, delay=0) as advance:
            assert advance is None  # pytest captures stderr: not a terminal
    assert not wanted(io.StringIO())


def test_a_terminal_gets_a_bar_and_warnings_on_lines_of_their_own():
    terminal = Terminal()
    with progress_bar(4, "render", "px", stream=terminal, delay=0) as advance:
        advance(2)
        with warnings.catch_warnings():
            warnings.simplefilter("always")
            shown_inside = warnings.showwarning
            warnings.warn("texture is large", UserWarning, stacklevel=1)
        advance(2)
    assert warnings.showwarning is not shown_inside  # put back after the bar
    text = terminal.getvalue()
    assert "render" in text and "2/4" in text
    line = next(part for part in text.replace("\r", "\n").split("\n") if "texture" in part)
    assert line.endswith("UserWarning: texture is large") and "%|" not in line


@pytest.mark.parametrize("adaptive", [False, True])
def test_render_reports_every_pixel_once(adaptive):
    scene = load_scene(SCENES / "cutouts.json")
    done = []
    plain = render(scene, samples=2, adaptive=adaptive)
    reported = render(scene, samples=2, adaptive=adaptive, progress=done.append)
    assert sum(done) == scene.camera.width * scene.camera.height
    assert len(done) > 1  # tile by tile, not all at the end
    assert (plain.rgb == reported.rgb).all()


def test_sweep_reports_every_scan_once():
    from raykit.io.linescan_json import load_line_scene
    from raykit.linescan.scan import sweep

    done = []
    scene = load_line_scene(SCENES / "linescan/conveyor.json")
    taken = sweep(scene, 12, progress=done.append)
    assert done == [1] * 12
    assert (taken.image == sweep(scene, 12).image).all()


@pytest.mark.slow
def test_the_command_line_prints_no_bar_into_captured_output(tmp_path):
    run = subprocess.run(
        [sys.executable, "-m", "raykit", "render", str(SCENES / "cutouts.json")]
        + ["-o", str(tmp_path / "c.png"), "--samples", "6"],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0
    assert run.stderr == ""
    assert run.stdout.startswith(f"wrote {tmp_path / 'c.png'} (480x320, 6x6 samples")


def test_execute_refuses_without_ipywidgets(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "ipywidgets", None)  # import ipywidgets raises ImportError
    spec = importlib.util.spec_from_file_location("execute", REPO / "notebooks/execute.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    before = {p: p.stat().st_mtime_ns for p in (REPO / "notebooks").glob("*.ipynb")}
    assert module.main([str(REPO / "notebooks/02_linescan_camera.ipynb")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith("notebooks/execute.py: error: ipywidgets is not installed")
    assert 'pip install -e ".[notebooks]"' in err
    assert {p: p.stat().st_mtime_ns for p in (REPO / "notebooks").glob("*.ipynb")} == before

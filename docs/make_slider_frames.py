"""The notebooks' sliders on the site: a picture for every stop of every slider, each drawn by
the notebook's own function.

    python docs/make_slider_frames.py [NOTEBOOK.ipynb ...]

A notebook's sliders (``ipywidgets.interact``) need a Python kernel behind them to redraw their
figure, and the site has none. This runs each notebook (default: every notebook in notebooks/)
in a kernel, as ``notebooks/execute.py`` does, up to each slider cell; then it calls the function
the sliders drive once for every stop of each slider, the other sliders at their first setting,
and keeps the figure the notebook shows for it. They go to ``docs/_static/sliders/NOTEBOOK/K/``
(the notebook's K-th slider cell, from 1), named by their content (a picture two settings share
is kept once), with ``sliders.json``:

    {"notebook": "01_rays_and_cameras.ipynb", "cell": 1, "code": "<sha256 of the cell's code>",
     "function": "explore", "first": "<the first setting's picture>",
     "controls": [{"name": "eye_x", "labels": ["-8.0", ...], "first": 16,
                   "frames": ["<picture of stop 0>", ...]}, ...]}

On the site (``docs/conf.py``), each slider cell's output is a plain HTML slider per control,
with the same stops, that shows these pictures (``docs/_static/sliders.js``): one slider at a
time, the others at their first setting, as the pictures were drawn. Every combination of
settings would take thousands of pictures; in Jupyter the sliders combine freely.

The pictures are stored as 256-colour PNGs (a quarter of the notebook's bytes; the figures are
flat colours and their anti-aliased edges). Run this after ``notebooks/execute.py``:
``tests/test_sliders.py`` checks that each cell's first picture is the figure of the first
setting that the notebook stores, and the site's build refuses a slider cell whose code
changed since its pictures were made.
"""

from __future__ import annotations

import base64
import hashlib
import io
import json
import shutil
import sys
import time
from collections.abc import Sequence
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
NOTEBOOKS = REPO / "notebooks"
SLIDERS = REPO / "docs" / "_static" / "sliders"
NEEDS = 'pip install -e ".[test,notebooks]"'

# run in the kernel first: remember every interactive widget (ipywidgets.interact makes one)
RECORD = """
import ipywidgets as _raykit_widgets

_raykit_sliders = []
_raykit_init = _raykit_widgets.interactive.__init__


def _raykit_record(self, *args, **kwargs):
    _raykit_init(self, *args, **kwargs)
    _raykit_sliders.append(self)


_raykit_widgets.interactive.__init__ = _raykit_record
"""

# the controls of the K-th interactive widget, and their stops, as the widgets set them out
DESCRIBE = """
import json as _raykit_json


def _raykit_stops(control):
    kind = type(control).__name__
    if kind in ("IntSlider", "FloatSlider"):
        count = round((control.max - control.min) / control.step)
        values = [control.min + k * control.step for k in range(count + 1)]
        if kind == "FloatSlider":
            values = [round(v, 10) for v in values]
        return values, [str(v) for v in values]
    if hasattr(control, "_options_values"):
        return list(control._options_values), [str(v) for v in control._options_labels]
    if kind == "Checkbox":
        return [False, True], ["False", "True"]
    raise TypeError(f"a {kind}, which has no list of stops (sliders, menus and checkboxes do)")


def _raykit_describe(k):
    sliders = _raykit_sliders[k]
    controls = []
    for control in sliders.kwargs_widgets:
        if isinstance(control, _raykit_widgets.fixed):
            continue
        try:
            values, labels = _raykit_stops(control)
        except TypeError as why:
            controls.append({"name": control._kwarg, "error": str(why)})
            continue
        if control.value in values:
            first = values.index(control.value)
        else:  # a float slider's first value between two stops: the nearer one
            first = min(range(len(values)), key=lambda i: abs(values[i] - control.value))
        controls.append({"name": control._kwarg, "labels": labels, "first": first})
    print(_raykit_json.dumps({"function": sliders.f.__name__, "controls": controls}))


def _raykit_draw(k, name=None, stop=0):
    sliders = _raykit_sliders[k]
    settings = {c._kwarg: c.value for c in sliders.kwargs_widgets}
    if name is not None:
        control = next(c for c in sliders.kwargs_widgets if c._kwarg == name)
        settings[name] = _raykit_stops(control)[0][stop]
    sliders.f(**settings)
"""


class SliderError(Exception):
    """A slider cell this command cannot draw: its one-line message names the notebook."""


def _run(client, notebook, source: str):
    """Run ``source`` in the notebook's kernel as a cell of its own; its outputs."""
    import nbformat

    cell = nbformat.v4.new_code_cell(source)
    notebook.cells.append(cell)
    try:
        client.execute_cell(cell, len(notebook.cells) - 1)
    finally:
        notebook.cells.pop()
    errors = [o for o in cell.outputs if o.get("output_type") == "error"]
    if errors:
        raise SliderError(f"{errors[0]['ename']}: {errors[0]['evalue']}")
    return cell.outputs


def _printed(outputs) -> str:
    return "".join(o.get("text", "") for o in outputs if o.get("output_type") == "stream")


def _picture(outputs) -> bytes:
    pictures = [o["data"]["image/png"] for o in outputs if "image/png" in o.get("data", {})]
    if len(pictures) != 1:
        raise SliderError(f"the slider's function showed {len(pictures)} figures, not one")
    return base64.b64decode(pictures[0])


def compact(png: bytes) -> bytes:
    """The figure as a 256-colour PNG, with the notes the notebook's PNG carries (its dpi, the
    size of its smallest text)."""
    from PIL import Image, PngImagePlugin

    image = Image.open(io.BytesIO(png))
    info = PngImagePlugin.PngInfo()
    for key, value in image.text.items():
        info.add_text(key, value)
    palette = image.convert("RGB").quantize(256, method=Image.Quantize.MEDIANCUT, dither=0)
    out = io.BytesIO()
    palette.save(out, "PNG", optimize=True, pnginfo=info, dpi=image.info.get("dpi", (72, 72)))
    return out.getvalue()


def cell_code(source: str) -> str:
    """What sliders.json's "code" is the hash of: the slider cell's code."""
    return hashlib.sha256(source.encode("utf-8")).hexdigest()


def _keep(folder: Path, png: bytes) -> str:
    data = compact(png)
    name = hashlib.sha256(data).hexdigest()[:16] + ".png"
    (folder / name).write_bytes(data)
    return name


WIDGET = "application/vnd.jupyter.widget-view+json"


def slider_cells(cells: list[dict]) -> list[int]:
    """The indices of the cells (a notebook's JSON) whose stored output is a widget (an
    ``interact``'s sliders): the cells the site shows as sliders, in order (what sliders.json's
    "cell" counts)."""
    return [
        index
        for index, cell in enumerate(cells)
        if cell["cell_type"] == "code"
        and any(WIDGET in o.get("data", {}) for o in cell.get("outputs", []))
    ]


def make(path: Path, out: Path = SLIDERS) -> list[Path]:
    """Draw the pictures of every slider cell of the notebook at ``path`` into
    ``out/NOTEBOOK/K/``; returns the sliders.json files written."""
    import nbformat
    from nbclient import NotebookClient

    notebook = nbformat.read(path, as_version=4)
    wanted = slider_cells(notebook.cells)
    target = out / path.stem
    if not wanted:
        shutil.rmtree(target, ignore_errors=True)
        return []
    cells = list(notebook.cells[: wanted[-1] + 1])
    client = NotebookClient(
        notebook,
        timeout=600,
        kernel_name="python3",
        resources={"metadata": {"path": str(path.parent)}},
    )
    written: list[Path] = []
    staging = out / f".{path.stem}.part"
    shutil.rmtree(staging, ignore_errors=True)
    staging.mkdir(parents=True)
    try:
        with client.setup_kernel():
            _run(client, notebook, RECORD + DESCRIBE)
            for index, cell in enumerate(cells):
                if cell.cell_type != "code":
                    continue
                client.execute_cell(cell, index)
                if index not in wanted:
                    continue
                number = wanted.index(index) + 1
                where = f"{path.name}: slider cell {number} (cell {index})"
                count = int(_printed(_run(client, notebook, "print(len(_raykit_sliders))")))
                if count != number:
                    raise SliderError(f"{where}: {count} interactive widgets so far, not {number}")
                try:
                    written.append(_draw(client, notebook, path.name, number, cell, staging))
                except SliderError as why:
                    raise SliderError(f"{where}: {why}") from None
        shutil.rmtree(target, ignore_errors=True)
        staging.rename(target)
        written = [target / p.relative_to(staging) for p in written]
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return written


def _draw(client, notebook, name: str, number: int, cell, staging: Path) -> Path:
    k = number - 1
    described = json.loads(_printed(_run(client, notebook, f"_raykit_describe({k})")))
    broken = [c for c in described["controls"] if "error" in c]
    if broken:
        raise SliderError(f"control {broken[0]['name']!r} is {broken[0]['error']}")
    folder = staging / str(number)
    folder.mkdir()
    first = _keep(folder, _picture(_run(client, notebook, f"_raykit_draw({k})")))
    for control in described["controls"]:
        control["frames"] = [
            first
            if stop == control["first"]
            else _keep(
                folder,
                _picture(_run(client, notebook, f"_raykit_draw({k}, {control['name']!r}, {stop})")),
            )
            for stop in range(len(control["labels"]))
        ]
    manifest = {
        "notebook": name,
        "cell": number,
        "code": cell_code(cell.source),
        "function": described["function"],
        "first": first,
        "controls": described["controls"],
    }
    (folder / "sliders.json").write_text(json.dumps(manifest, indent=1) + "\n")
    return folder / "sliders.json"


def main(argv: Sequence[str] | None = None) -> int:
    try:
        import ipywidgets  # noqa: F401
        import nbclient  # noqa: F401
    except ImportError as missing:
        print(
            f"docs/make_slider_frames.py: error: {missing.name} is not installed; it runs the "
            f"notebooks' sliders in a kernel: {NEEDS}",
            file=sys.stderr,
        )
        return 2
    names = sys.argv[1:] if argv is None else argv
    paths = [Path(p) for p in names] or sorted(NOTEBOOKS.glob("*.ipynb"))
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        print(f"docs/make_slider_frames.py: error: {missing[0]}: no such notebook", file=sys.stderr)
        return 2
    for path in paths:
        start = time.perf_counter()
        try:
            written = make(path.resolve())
        except SliderError as why:
            print(f"docs/make_slider_frames.py: error: {why}", file=sys.stderr)
            return 1
        pictures = sum(len(list(p.parent.glob("*.png"))) for p in written)
        print(
            f"{path.name}: {len(written)} slider cell(s), {pictures} pictures, "
            f"{time.perf_counter() - start:.1f} s",
            flush=True,
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())

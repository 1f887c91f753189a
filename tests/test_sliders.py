"""The pictures behind the notebooks' sliders on the site (docs/make_slider_frames.py) are there
for every slider cell, drawn by the cell's code as it is now, and their first picture is the
figure of the sliders' first setting that the notebook stores (the cell after the sliders draws
it), so that a notebook rerun whose figures changed shows up as pictures to draw again.
tests/test_site.py moves the sliders in a browser."""

from __future__ import annotations

import base64
import importlib.util
import io
import json

import numpy as np
import pytest
from PIL import Image

from conftest import REPO

SLIDERS = REPO / "docs" / "_static" / "sliders"


def _maker():
    spec = importlib.util.spec_from_file_location(
        "make_slider_frames", REPO / "docs" / "make_slider_frames.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


MAKER = _maker()
NOTEBOOKS = sorted((REPO / "notebooks").glob("*.ipynb"))


def _slider_cells():
    for path in NOTEBOOKS:
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        for number, index in enumerate(MAKER.slider_cells(cells), start=1):
            yield pytest.param(path, cells, index, number, id=f"{path.stem}-{number}")


SLIDER_CELLS = list(_slider_cells())


def test_the_notebooks_have_slider_cells_and_no_pictures_are_left_over():
    assert {p.values[0].stem for p in SLIDER_CELLS} >= {"01_rays_and_cameras", "02_linescan_camera"}
    kept = {(m.parent.parent.name, int(m.parent.name)) for m in SLIDERS.glob("*/*/sliders.json")}
    assert kept == {(p.values[0].stem, p.values[3]) for p in SLIDER_CELLS}
    folders = {p.parent for p in SLIDERS.glob("*/*/*")}
    assert folders == {SLIDERS / stem / str(number) for stem, number in kept}


@pytest.mark.parametrize(("path", "cells", "index", "number"), SLIDER_CELLS)
def test_pictures_are_drawn_by_the_cells_code_as_it_is(path, cells, index, number):
    folder = SLIDERS / path.stem / str(number)
    manifest = json.loads((folder / "sliders.json").read_text())
    assert manifest["notebook"] == path.name and manifest["cell"] == number
    assert manifest["code"] == MAKER.cell_code("".join(cells[index]["source"])), (
        f"{path.name}: slider cell {number} changed: run python docs/make_slider_frames.py"
    )
    named = {manifest["first"]}
    for control in manifest["controls"]:
        assert len(control["frames"]) == len(control["labels"]) >= 2, control["name"]
        assert control["frames"][control["first"]] == manifest["first"]
        named |= set(control["frames"])
    assert named == {p.name for p in folder.glob("*.png")}


@pytest.mark.parametrize(("path", "cells", "index", "number"), SLIDER_CELLS)
def test_first_picture_is_the_figure_the_notebook_stores_for_the_first_setting(
    path, cells, index, number
):
    following = next(
        c for c in cells[index + 1 :] if c["cell_type"] == "code" and _png(c) is not None
    )
    stored = Image.open(io.BytesIO(MAKER.compact(_png(following))))
    manifest = json.loads((SLIDERS / path.stem / str(number) / "sliders.json").read_text())
    first = Image.open(SLIDERS / path.stem / str(number) / manifest["first"])
    assert first.size == stored.size, (
        f"{path.name}: slider cell {number}: the notebook's figure changed since the pictures "
        "were drawn: run python docs/make_slider_frames.py"
    )
    same = np.all(np.asarray(first.convert("RGB")) == np.asarray(stored.convert("RGB")), axis=-1)
    assert same.mean() >= 0.999, (
        f"{path.name}: slider cell {number}: the notebook's figure changed since the pictures "
        "were drawn: run python docs/make_slider_frames.py"
    )


def _png(cell) -> bytes | None:
    for output in cell.get("outputs", []):
        if "image/png" in output.get("data", {}):
            return base64.b64decode(output["data"]["image/png"])
    return None

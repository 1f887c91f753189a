"""Every picture the notebooks and the site show is one a back row can read when it is projected
(the rule is raykit.io.legibility's: filling a 1920 x 1080 screen it is blown up at most 1.6
times, and its smallest text is at least 1/40 of the screen's height there), and no figure's
text lies on other text or on a drawn line.

The pictures: the notebooks' stored figures, the pictures their Markdown links, every picture a
page of the site shows, and every picture in docs/images, docs/gallery and docs/benchmarks
(the lecture map points at them all).

What is measured, and by whom:

* A picture's size is read from its PNG's pixels: every picture, renders included. A render's
  pixels are the rays it traced, so a render passes only by being rendered that large.
* A figure's text cannot be measured from its pixels alone, and a figure is not asked what size
  its text is. raykit.io.images.figure_png, which stores every figure (diagrams, benchmark
  plots, the notebooks' outputs), draws it into the PNG with raykit.io.legibility.measuring:
  each text artist matplotlib draws, its box in the stored picture after drawing and the height
  of its lines as the renderer laid them out, and every line, patch edge and marker the axes
  drew, with what overlaps; that record is written into the PNG. This test reads the record and
  ties it to the picture: its size must be the PNG's, and each text box must hold drawn pixels.
  A matplotlib picture without a record was not stored that way, and fails.
* Where the figures come from code the tests run, they are measured afresh as well: the
  diagram functions in tests/test_diagrams.py (``test_diagram_labels_are_clear``), and the
  pictures docs/make_images.py draws in tests/test_reproducible.py, whose fresh record must
  agree with the committed one.

A render has no text: it is held to the size rule only. A line-scan sweep's pixels are its
camera's pixels by its scans, so the scenes it is made from have as many of both as the rule asks.
"""

from __future__ import annotations

import base64
import io
import json
import re

import numpy as np
import pytest
from PIL import Image

from conftest import REPO
from raykit.io.legibility import read_layout, size_problems, text_problems

SHOWN_FOLDERS = ("docs/images", "docs/gallery", "docs/benchmarks")
IMAGE_LINK = re.compile(r"!\[[^\]]*\]\(([^)\s]+\.png)\)")


def _pictures() -> dict[str, bytes]:
    found: dict[str, bytes] = {}
    for notebook in sorted((REPO / "notebooks").glob("*.ipynb")):
        for k, cell in enumerate(json.loads(notebook.read_text())["cells"]):
            for n, output in enumerate(cell.get("outputs", [])):
                png = output.get("data", {}).get("image/png")
                if png:
                    found[f"{notebook.name} cell {k} output {n}"] = base64.b64decode(png)
            if cell["cell_type"] == "markdown":
                for link in IMAGE_LINK.findall("".join(cell["source"])):
                    path = (notebook.parent / link).resolve()
                    found[str(path.relative_to(REPO))] = path.read_bytes()
    for page in sorted((REPO / "docs").rglob("*.md")):
        if "_build" in page.parts:
            continue
        for link in IMAGE_LINK.findall(page.read_text()):
            path = (page.parent / link).resolve()
            found[str(path.relative_to(REPO))] = path.read_bytes()
    for folder in SHOWN_FOLDERS:
        for path in sorted((REPO / folder).glob("*.png")):
            found[f"{folder}/{path.name}"] = path.read_bytes()
    return found


PICTURES = _pictures()
NAMES = sorted(PICTURES)


def _is_figure(image: Image.Image) -> bool:
    return str(image.info.get("Software", "")).startswith("Matplotlib")


def _figures() -> list[str]:
    return [n for n in NAMES if _is_figure(Image.open(io.BytesIO(PICTURES[n])))]


def test_the_pictures_shown_are_all_checked():
    for folder in SHOWN_FOLDERS:
        for path in (REPO / folder).glob("*.png"):
            assert f"{folder}/{path.name}" in PICTURES
    assert len(_figures()) > 60 and len(NAMES) - len(_figures()) > 15


@pytest.mark.parametrize("name", NAMES)
def test_picture_is_large_enough_to_project(name):
    image = Image.open(io.BytesIO(PICTURES[name]))
    assert not size_problems(*image.size), f"{name}: {size_problems(*image.size)}"


@pytest.mark.parametrize("name", _figures())
def test_figure_text_is_measured_readable_and_clear(name):
    png = PICTURES[name]
    layout = read_layout(png)
    assert layout is not None, f"{name}: stored without raykit.io.images.figure_png's record"
    pixels = np.asarray(Image.open(io.BytesIO(png)).convert("L"), float)
    assert layout.size == (pixels.shape[1], pixels.shape[0]), f"{name}: record of another size"
    for text in layout.texts:  # the record belongs to this picture: its texts are drawn here
        x0, y0, x1, y1 = (int(round(v)) for v in text.box)
        inside = pixels[max(y0, 0) : y1, max(x0, 0) : x1]
        assert inside.size and np.ptp(inside) > 60, f"{name}: nothing drawn at {text.text!r}"
    assert not text_problems(*layout.size, layout.smallest_text_px), name
    assert not layout.problems, f"{name}: {layout.problems}"

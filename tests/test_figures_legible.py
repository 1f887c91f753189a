"""Every stored figure is one a back row can read when it is projected (the rule is
raykit.io.images's: at FIGURE_DPI or more, blown up at most 1.6 times to fill a 1920 x 1080
screen, its smallest text at least 1/40 of the screen's height there). The figures are the
notebooks' stored PNG outputs and the pictures in docs/images/ that matplotlib drew (the
renders, pictures of scenes with no text, are the size of their scene). The size of a figure's
smallest text is written into its PNG as it is saved (raykit.io.images.figure_png, from the text
the figure really draws); a figure without it was not saved that way and fails."""

from __future__ import annotations

import base64
import io
import json

import pytest
from PIL import Image

from conftest import REPO
from raykit.io.images import TEXT_KEY, legibility_problems


def _stored_figures() -> list[tuple[str, bytes]]:
    found = []
    for notebook in sorted((REPO / "notebooks").glob("*.ipynb")):
        for k, cell in enumerate(json.loads(notebook.read_text())["cells"]):
            for n, output in enumerate(cell.get("outputs", [])):
                png = output.get("data", {}).get("image/png")
                if png:
                    found.append((f"{notebook.name} cell {k} output {n}", base64.b64decode(png)))
    for path in sorted((REPO / "docs" / "images").glob("*.png")):
        found.append((f"docs/images/{path.name}", path.read_bytes()))
    return found


FIGURES = [(name, png) for name, png in _stored_figures()]


def _is_figure(image: Image.Image) -> bool:
    return str(image.info.get("Software", "")).startswith("Matplotlib")


def test_there_are_figures_to_check():
    assert sum(_is_figure(Image.open(io.BytesIO(png))) for _, png in FIGURES) > 40


@pytest.mark.parametrize("name, png", FIGURES, ids=[name for name, _ in FIGURES])
def test_stored_figure_reads_on_a_projector(name, png):
    image = Image.open(io.BytesIO(png))
    if not _is_figure(image):
        pytest.skip("a render (a picture of a scene, no text), not a figure")
    assert TEXT_KEY in image.info, f"{name}: saved without raykit.io.images.figure_png"
    dpi = image.info.get("dpi", (None,))[0]
    text = image.info[TEXT_KEY]
    text_px = None if text == "none" else float(text)
    assert not legibility_problems(*image.size, dpi, text_px), name

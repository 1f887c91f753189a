"""docs/lecture-map.md cannot rot: each notebook cell, function, test and figure it names exists,
the notebooks take the slide items in the lecture's order, and every item's section of its
notebook has a code cell that ran and a figure."""

import ast
import importlib
import json
import re
from itertools import pairwise
from pathlib import Path

import pytest

from conftest import REPO

MAP = REPO / "docs" / "lecture-map.md"


def _rows() -> list[list[str]]:
    rows = []
    for line in MAP.read_text().splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split(" | ")]
        if len(cells) == 6 and cells[0].isdigit():
            rows.append(cells)
    return rows


def test_map_has_the_twenty_six_slide_items_in_order():
    assert [int(row[0]) for row in _rows()] == list(range(1, 27))


def _place(notebook: str) -> tuple[str, int]:
    """(notebook path, index of the first cell holding the heading's words) of a map row's cell."""
    path, words = re.fullmatch(r"`([^`]+)`, at `([^`]+)`", notebook).groups()
    cells = json.loads((REPO / path).read_text())["cells"]
    found = [k for k, cell in enumerate(cells) if words in "".join(cell["source"])]
    assert found, (path, words)
    return path, found[0]


def test_the_notebooks_take_the_items_in_the_lectures_order():
    # item by item: the notebook's file name never goes back, and within one notebook the
    # item's cell never comes before the previous item's
    places = [(int(row[0]), *_place(row[2])) for row in _rows()]
    for (item, path, cell), (next_item, next_path, next_cell) in pairwise(places):
        assert Path(next_path).name >= Path(path).name, (
            f"item {next_item} is in {next_path}, before item {item}'s {path}"
        )
        if next_path == path:
            assert next_cell >= cell, (
                f"item {next_item} (cell {next_cell}) comes before item {item} (cell {cell}) "
                f"in {path}"
            )


@pytest.mark.parametrize("row", _rows(), ids=lambda row: row[0])
def test_every_name_in_the_map_exists(row):
    _, _, notebook, functions, tests, figures = row
    _place(notebook)
    for name in re.findall(r"`([^`]+)`", functions):
        module, attribute = name.rsplit(".", 1)
        assert hasattr(importlib.import_module(module), attribute), name
    for name in re.findall(r"`([^`]+)`", tests):
        file, test = name.split("::")
        tree = ast.parse((REPO / file).read_text())
        assert test in {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}, name
    for name in re.findall(r"`([^`]+)`", figures):
        assert (REPO / name).is_file(), name


def _sections() -> list[tuple[list[str], list[dict]]]:
    """Each map row with its notebook's cells from the item's cell up to the next item's (or,
    when the next item is in another notebook, to the notebook's end)."""
    places = [_place(row[2]) for row in _rows()]
    sections = []
    for k, (row, (path, start)) in enumerate(zip(_rows(), places, strict=True)):
        cells = json.loads((REPO / path).read_text())["cells"]
        following = places[k + 1] if k + 1 < len(places) else None
        end = following[1] if following and following[0] == path else len(cells)
        sections.append((row, cells[start : max(end, start + 1)]))
    return sections


def _images_shown(cells: list[dict], path: str) -> list[str]:
    """Images a section draws (PNG outputs) or shows (Markdown images of files that exist)."""
    found = []
    for cell in cells:
        if cell["cell_type"] == "code":
            found += [
                "output" for out in cell.get("outputs", []) if "image/png" in out.get("data", {})
            ]
        else:
            for target in re.findall(r"!\[[^\]]*\]\(([^)]+)\)", "".join(cell["source"])):
                if (REPO / Path(path).parent / target).is_file():
                    found.append(target)
    return found


SECTIONS = _sections()


@pytest.mark.parametrize("row, cells", SECTIONS, ids=[row[0] for row, _ in SECTIONS])
def test_every_item_has_a_cell_that_ran_and_a_figure(row, cells):
    path = re.match(r"`([^`]+)`", row[2]).group(1)
    ran = [
        c for c in cells if c["cell_type"] == "code" and c.get("execution_count") and c["outputs"]
    ]
    assert ran, f"item {row[0]}: no code cell with stored outputs in its section of {path}"
    shown = _images_shown(cells, path)
    assert shown, f"item {row[0]}: no figure in its section of {path}"
    if "cell figure" in row[5]:  # the map promises a figure drawn by the item's own cells
        assert "output" in shown, f"item {row[0]}: its cells draw no figure"


QUOTED = re.compile(r'"([^"]+)"')


@pytest.mark.parametrize("row, cells", SECTIONS, ids=[row[0] for row, _ in SECTIONS])
def test_the_slides_words_quoted_in_the_map_are_in_the_items_section(row, cells):
    # the map quotes the slide only where its notebook section does, with the same words
    # (bold and case aside), so a quotation in either is the slide's, not a rewording
    text = " ".join("".join(cell["source"]) for cell in cells if cell["cell_type"] == "markdown")
    text = re.sub(r"^[ \t]*>[ \t]?", "", text, flags=re.M)  # a block quote's marks
    text = " ".join(text.replace("**", "").split()).lower()
    for quote in QUOTED.findall(row[1]):
        assert " ".join(quote.split()).lower() in text, f"item {row[0]}: {quote!r}"

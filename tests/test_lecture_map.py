"""docs/lecture-map.md cannot rot: each notebook cell, function, test and figure it names exists,
and the notebooks take the slide items in the lecture's order."""

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


def test_map_has_the_fifteen_slide_items_in_order():
    assert [int(row[0]) for row in _rows()] == list(range(1, 16))


def _place(notebook: str) -> tuple[str, int]:
    """(notebook path, index of the first cell holding the quoted words) of a map row's cell."""
    path, words = re.fullmatch(r'`([^`]+)` "(.+)"', notebook).groups()
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

"""docs/lecture-map.md cannot rot: each notebook cell, function, test and figure it names exists."""

import ast
import importlib
import json
import re

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


@pytest.mark.parametrize("row", _rows(), ids=lambda row: row[0])
def test_every_name_in_the_map_exists(row):
    _, _, notebook, functions, tests, figures = row
    path, words = re.fullmatch(r'`([^`]+)` "(.+)"', notebook).groups()
    cells = json.loads((REPO / path).read_text())["cells"]
    assert any(words in "".join(cell["source"]) for cell in cells), (path, words)
    for name in re.findall(r"`([^`]+)`", functions):
        module, attribute = name.rsplit(".", 1)
        assert hasattr(importlib.import_module(module), attribute), name
    for name in re.findall(r"`([^`]+)`", tests):
        file, test = name.split("::")
        tree = ast.parse((REPO / file).read_text())
        assert test in {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}, name
    for name in re.findall(r"`([^`]+)`", figures):
        assert (REPO / name).is_file(), name

"""Every figure in tests/support/baselines.py looks as its baseline image does (within a tolerance);
regenerate the baselines with ``python tests/support/baselines.py`` after a deliberate change."""

import pytest
from matplotlib.testing.compare import compare_images

import baselines


@pytest.mark.parametrize("name", sorted(baselines.FIGURES))
def test_figure_matches_its_baseline(name, tmp_path):
    actual = tmp_path / f"{name}.png"
    baselines.draw(name, actual)
    expected = baselines.FOLDER / f"{name}.png"
    assert compare_images(str(expected), str(actual), tol=baselines.TOLERANCE) is None


def test_every_baseline_image_has_a_figure():
    names = {p.stem for p in baselines.FOLDER.glob("*.png")}
    assert names == set(baselines.FIGURES)

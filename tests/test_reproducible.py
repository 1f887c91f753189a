"""Everything committed that a command makes is what that command makes today."""

import importlib.util

import numpy as np
from matplotlib.testing.compare import compare_images
from PIL import Image

from conftest import REPO


def _load_docs_maker():
    spec = importlib.util.spec_from_file_location("make_images", REPO / "docs/make_images.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_and_docs_images_are_what_their_commands_make(tmp_path):
    maker = _load_docs_maker()
    maker.make(tmp_path)
    names = maker.all_outputs()
    assert sorted(names) == sorted(p.name for p in (REPO / "docs/images").glob("*.png"))
    for name in names:
        committed = REPO / "docs/images" / name
        if any(word in name for word in ("diagram", "rays", "camera", "math")):
            # matplotlib figures: anti-aliasing may vary a little between platforms
            assert compare_images(str(committed), str(tmp_path / name), tol=3) is None, name
            continue
        fresh = np.asarray(Image.open(tmp_path / name).convert("RGB"))
        pinned = np.asarray(Image.open(committed).convert("RGB"))
        assert fresh.shape == pinned.shape, name
        # bit-identical on one platform; allow a silhouette pixel or two to round differently
        assert np.mean(np.all(fresh == pinned, axis=-1)) >= 0.999, name

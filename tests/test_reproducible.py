"""Everything committed that a command makes is what that command makes today."""

import importlib.util

import numpy as np
from matplotlib.testing.compare import compare_images
from PIL import Image

from conftest import REPO
from raykit.io.legibility import read_layout


def _load_docs_maker():
    spec = importlib.util.spec_from_file_location("make_images", REPO / "docs/make_images.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_and_docs_images_are_what_their_commands_make(tmp_path):
    maker = _load_docs_maker()
    maker.make(tmp_path, reduce=True)
    names = maker.all_outputs()
    assert sorted(names) == sorted(p.name for p in (REPO / "docs/images").glob("*.png"))
    for name in names:
        committed = REPO / "docs/images" / name
        if any(word in name for word in ("diagram", "rays", "camera", "math")):
            # matplotlib figures: anti-aliasing may vary a little between platforms
            assert compare_images(str(committed), str(tmp_path / name), tol=3) is None, name
            # and what their draw measured (tests/test_figures_legible.py reads the committed
            # record) is what it measures today: no label on a line, text a projector shows
            fresh, pinned = (read_layout(p.read_bytes()) for p in (tmp_path / name, committed))
            assert fresh.problems == pinned.problems == [], (name, fresh.problems)
            assert fresh.size == pinned.size, name
            assert abs(fresh.smallest_text_px - pinned.smallest_text_px) < 0.5, name
            continue
        fresh = np.asarray(Image.open(tmp_path / name).convert("RGB"))
        if name in maker.REDUCED_WIDTH:
            # rendered at the scene's own size here (at the committed size it takes tens of
            # seconds): the committed picture, scaled down to it, shows the same within the
            # sampling noise (a picture moved by 2 pixels is 20 off, another scene 60)
            pinned = Image.open(committed).convert("RGB")
            small = np.asarray(pinned.resize(fresh.shape[1::-1], Image.Resampling.BOX), float)
            assert np.sqrt(np.mean((small - fresh) ** 2)) < 5, name
            continue
        pinned = np.asarray(Image.open(committed).convert("RGB"))
        assert fresh.shape == pinned.shape, name
        # bit-identical on one platform; allow a silhouette pixel or two to round differently
        assert np.mean(np.all(fresh == pinned, axis=-1)) >= 0.999, name

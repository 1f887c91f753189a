"""Everything committed that a command makes is what that command makes today."""

import importlib.util
import shutil
import subprocess

import numpy as np
import pytest
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
    for name, _ in maker.IMAGES:
        fresh = np.asarray(Image.open(tmp_path / name).convert("RGB"))
        committed = np.asarray(Image.open(REPO / "docs/images" / name).convert("RGB"))
        assert fresh.shape == committed.shape, name
        # bit-identical on one platform; allow a silhouette pixel or two to round differently
        assert np.mean(np.all(fresh == committed, axis=-1)) >= 0.999, name


@pytest.mark.skipif(shutil.which("ruff") is None, reason="ruff is not installed")
def test_code_is_ruff_clean():
    run = subprocess.run(["ruff", "check", "--no-cache", str(REPO)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout

import numpy as np
import pytest
from PIL import Image

from raykit.io.images import quantize, save_image


def test_quantising_rounds_halves_up_and_clamps():
    values = np.array([0.3, 0.5 / 255, 1.5 / 255, -0.2, 1.7, 1.0])
    assert quantize(values).tolist() == [77, 1, 2, 0, 255, 255]


def test_saved_png_is_8_bit_rgb_with_the_quantised_values(tmp_path):
    rgb = np.zeros((2, 3, 3))
    rgb[0, 1] = [0.3, 0.6, 1.0]
    save_image(rgb, tmp_path / "x.png")
    image = Image.open(tmp_path / "x.png")
    assert image.mode == "RGB" and image.size == (3, 2)
    assert np.asarray(image)[0, 1].tolist() == [77, 153, 255]


def test_failed_write_leaves_neither_output_nor_temporary_file(tmp_path, monkeypatch):
    def half_then_fail(self, stream, format=None):
        stream.write(b"\x89PNG half an image")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", half_then_fail)
    target = tmp_path / "x.png"
    target.write_bytes(b"old")
    with pytest.raises(OSError):
        save_image(np.zeros((2, 2, 3)), target)
    assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["x.png"]


def test_unknown_suffix_is_refused_before_anything_is_written(tmp_path):
    with pytest.raises(ValueError, match="unknown image suffix"):
        save_image(np.zeros((1, 1, 3)), tmp_path / "x.notanimage")
    assert list(tmp_path.iterdir()) == []


def test_a_write_that_cannot_start_names_the_users_path_not_the_temporary_file(tmp_path):
    # the folder vanishing between raykit's early check and the write: the error is about
    # out/classic.png, never about a hidden .classic.png.XXXX.part beside it
    out = tmp_path / "out" / "classic.png"
    with pytest.raises(OSError) as raised:
        save_image(np.zeros((2, 2, 3)), out)
    assert raised.value.filename == str(out)
    assert ".part" not in str(raised.value)

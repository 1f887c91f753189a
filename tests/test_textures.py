import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from PIL import Image

from conftest import SCENES
from raykit.io import textures
from raykit.io.scene_json import scene_from_dict
from raykit.io.textures import CACHED_FROM, Texture, to_rgba8


def test_16_bit_grey_is_scaled_not_clipped():
    image = Image.fromarray(np.array([[0, 256, 32768, 65535]], np.uint16))
    assert to_rgba8(image)[0, :, 0].tolist() == [0, 1, 128, 255]


def test_16_bit_to_8_bits_keeps_the_high_byte_not_the_rounded_scale(tmp_path):
    # v >> 8, not round(v·255/65535): 255 -> 0 (not 1), 65280 -> 255 (not 254)
    grey = Image.fromarray(np.array([[0, 255, 256, 32767, 32768, 65280, 65535]], np.uint16))
    assert to_rgba8(grey)[0, :, 0].tolist() == [0, 0, 1, 127, 128, 255, 255]
    # 16-bit RGB, which Pillow decodes itself, follows the same rule
    row = [(255, 65280, 32768), (65535, 256, 127)]
    path = tmp_path / "rgb16.png"
    path.write_bytes(_png_16_bit_rgb(row))
    with Image.open(path) as image:
        assert to_rgba8(image)[0].tolist() == [[0, 255, 128, 255], [255, 1, 0, 255]]


def _png_16_bit_rgb(row: list[tuple[int, int, int]]) -> bytes:
    """A one-row 16-bit RGB PNG, written by hand (Pillow writes no such file)."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        crc = zlib.crc32(kind + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)

    header = struct.pack(">IIBBBBB", len(row), 1, 16, 2, 0, 0, 0)
    pixels = b"\x00" + b"".join(struct.pack(">HHH", *texel) for texel in row)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(pixels))
        + chunk(b"IEND", b"")
    )


def test_palette_transparency_becomes_alpha():
    image = Image.fromarray(np.array([[0, 1]], np.uint8), "P")
    image.putpalette([10, 20, 30, 200, 100, 50])
    image.info["transparency"] = 0
    assert to_rgba8(image).tolist() == [[[10, 20, 30, 0], [200, 100, 50, 255]]]


def test_grey_and_rgb_without_alpha_are_opaque():
    grey = Image.fromarray(np.array([[7, 200]], np.uint8), "L")
    assert to_rgba8(grey).tolist() == [[[7, 7, 7, 255], [200, 200, 200, 255]]]
    rgb = Image.fromarray(np.array([[[1, 2, 3]]], np.uint8), "RGB")
    assert to_rgba8(rgb).tolist() == [[[1, 2, 3, 255]]]


def test_texture_reads_its_header_at_once_and_decodes_on_first_use(tmp_path):
    Image.new("RGBA", (5, 3), (9, 8, 7, 6)).save(tmp_path / "t.png")
    texture = Texture(tmp_path / "t.png", "scene.json", "billboards[0].image")
    assert (texture.width, texture.height) == (5, 3)
    assert vars(texture)["_rgba"] is None  # nothing decoded yet
    assert texture.rgba.shape == (3, 5, 4)
    assert texture.rgba[0, 0].tolist() == [9, 8, 7, 6]


def test_billboards_that_name_one_file_share_one_texture(tmp_path):
    Image.new("RGBA", (4, 4)).save(tmp_path / "a.png")
    Image.new("RGBA", (4, 4)).save(tmp_path / "b.png")
    boards = _scene_of_textures(tmp_path, ["a.png", "b.png", "./a.png"]).billboards
    assert boards[2].texture is boards[0].texture and boards[1].texture is not boards[0].texture


def _scene_of_textures(folder, images: list[str]):
    """A scene with a billboard for each of ``images`` (file names in ``folder``)."""
    boards = [
        {"upper_left": [k, 1, 0], "lower_left": [k, 0, 0], "upper_right": [k + 1, 1, 0],
         "image": image}
        for k, image in enumerate(images)
    ]  # fmt: skip
    camera = {"eye": [0, 0, 5], "lookat": [0, 0, 0], "up": [0, 1, 0], "fov_angle": 40,
              "width": 8, "height": 8}  # fmt: skip
    return scene_from_dict({"camera": camera, "billboards": boards}, folder=folder)


def test_committed_textures_are_what_the_generator_makes(tmp_path):
    script = SCENES / "textures" / "make_textures.py"
    subprocess.run([sys.executable, str(script), str(tmp_path)], check=True, capture_output=True)
    made = sorted(p.name for p in tmp_path.glob("*.png"))
    assert made == sorted(p.name for p in (SCENES / "textures").glob("*.png"))
    for name in made:
        fresh, committed = Image.open(tmp_path / name), Image.open(SCENES / "textures" / name)
        assert fresh.mode == committed.mode, name
        assert np.array_equal(to_rgba8(fresh), to_rgba8(committed)), name


def _large_texture(path, seed: int) -> np.ndarray:
    """A seeded RGBA texture of CACHED_FROM texels (large enough to be cached), written to
    ``path``; its texels ``(H, W, 4)``."""
    side = int(CACHED_FROM**0.5)
    rgba = np.random.default_rng(seed).integers(0, 256, (side, side, 4), dtype=np.uint8)
    Image.fromarray(rgba, "RGBA").save(path)
    return rgba


def _texels(path) -> np.ndarray:
    """The texels of a texture file, read as a scene's billboard reads them."""
    return Texture(path, "scene.json", "billboards[0].image").rgba


def _cached_files(cache) -> list:
    return sorted((cache / "raykit" / "textures").glob("*.rgba"))


def _decodes(monkeypatch) -> list:
    """A list that grows by one at each texture decode, from now on."""
    calls = []
    decode = Texture._decode
    monkeypatch.setattr(Texture, "_decode", lambda self, *a: calls.append(1) or decode(self, *a))
    return calls


def test_a_large_texture_is_decoded_once_and_then_read_from_the_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    made = _large_texture(tmp_path / "t.png", seed=1)
    decodes = _decodes(monkeypatch)
    first = _texels(tmp_path / "t.png")
    again = _texels(tmp_path / "t.png")
    assert len(decodes) == 1 and len(_cached_files(tmp_path / "cache")) == 1
    assert type(again) is np.ndarray and again.dtype == np.uint8
    assert not first.flags.writeable and not again.flags.writeable  # nobody's to change
    assert np.array_equal(first, made) and np.array_equal(again, made)


def test_an_edited_texture_file_is_decoded_anew(tmp_path, monkeypatch):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    _large_texture(tmp_path / "t.png", seed=1)
    _texels(tmp_path / "t.png")  # cached
    edited = _large_texture(tmp_path / "t.png", seed=2)  # same name, size and header
    decodes = _decodes(monkeypatch)
    rgba = _texels(tmp_path / "t.png")
    assert len(decodes) == 1 and np.array_equal(rgba, edited)
    assert len(_cached_files(tmp_path / "cache")) == 2


def test_a_small_texture_is_decoded_each_time_and_never_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    Image.new("RGBA", (16, 16), (1, 2, 3, 4)).save(tmp_path / "t.png")
    for _ in range(2):
        assert _texels(tmp_path / "t.png")[0, 0].tolist() == [1, 2, 3, 4]
    assert _cached_files(tmp_path / "cache") == []


def test_the_cache_drops_the_least_recently_used_decodes_beyond_its_size(tmp_path, monkeypatch):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    one_decode = CACHED_FROM * 4  # a kept decode: the texels' bytes alone
    monkeypatch.setattr(textures, "CACHE_BYTES", 2 * one_decode)
    paths = [tmp_path / f"t{k}.png" for k in range(3)]
    made = [_large_texture(path, seed=k) for k, path in enumerate(paths)]
    for path in paths[:2]:
        _texels(path)
    for kept in _cached_files(tmp_path / "cache"):
        os.utime(kept, (1, 1))  # both long unused
    _texels(paths[0])  # t0 read from the cache: used now
    _texels(paths[2])  # a third decode: t1, least recently used, goes
    assert len(_cached_files(tmp_path / "cache")) == 2
    decodes = _decodes(monkeypatch)
    for k in (0, 2, 1):
        assert np.array_equal(_texels(paths[k]), made[k])
    assert decodes == [1]  # t1's alone


def test_a_cache_that_cannot_be_written_only_decodes(tmp_path, monkeypatch):
    (tmp_path / "file").write_text("not a folder")
    for variable in ("RAYKIT_CACHE_DIR", "XDG_CACHE_HOME", "HOME"):
        monkeypatch.setenv(variable, str(tmp_path / "file"))
    made = _large_texture(tmp_path / "t.png", seed=3)
    assert textures.cache_folder() is None
    assert np.array_equal(_texels(tmp_path / "t.png"), made)


def test_the_cache_is_looked_over_only_when_this_process_may_have_filled_it(tmp_path, monkeypatch):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    one_decode = CACHED_FROM * 4
    monkeypatch.setattr(textures, "CACHE_BYTES", 3 * one_decode)
    looks = []
    evict = textures._evict
    monkeypatch.setattr(textures, "_evict", lambda folder: looks.append(1) or evict(folder))
    paths = [tmp_path / f"t{k}.png" for k in range(5)]
    for k, path in enumerate(paths):
        _large_texture(path, seed=k)
    for path in paths[:3]:
        _texels(path)
    assert looks == [1]  # the first write looks; two more fit in the room it saw
    _texels(paths[3])  # the room is used up: it looks again, and drops one
    _texels(paths[4])  # and again
    assert looks == [1, 1, 1] and len(_cached_files(tmp_path / "cache")) == 3


def test_textures_decoded_on_threads_at_once_are_each_decoded_once_and_kept(tmp_path, monkeypatch):
    # as the compiled engine's prepare decodes a scene's (pool.each_at_once): the cache's
    # bookkeeping of the room its writes took is shared by the threads
    from concurrent.futures import ThreadPoolExecutor

    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    made = [_large_texture(tmp_path / f"t{k}.png", seed=k) for k in range(4)]
    loaded = [
        Texture(tmp_path / f"t{k}.png", "scene.json", f"billboards[{k}].image") for k in range(4)
    ]
    decodes = _decodes(monkeypatch)
    with ThreadPoolExecutor(2) as pool:
        texels = list(pool.map(lambda texture: texture.rgba, loaded))
    assert len(decodes) == 4 and all(texture.decoded for texture in loaded)
    assert all(np.array_equal(t, m) for t, m in zip(texels, made, strict=True))
    assert len(_cached_files(tmp_path / "cache")) == 4


def test_a_kept_decode_of_the_wrong_size_is_no_decode_and_is_decoded_anew(tmp_path, monkeypatch):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    made = _large_texture(tmp_path / "t.png", seed=4)
    _texels(tmp_path / "t.png")
    (kept,) = _cached_files(tmp_path / "cache")
    kept.write_bytes(kept.read_bytes()[:-1])  # cut short, as by a full disk
    decodes = _decodes(monkeypatch)
    assert np.array_equal(_texels(tmp_path / "t.png"), made) and decodes == [1]
    assert kept.stat().st_size == made.nbytes  # kept whole again


def test_an_older_formats_decodes_count_in_the_cache_and_go_first(tmp_path, monkeypatch):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    folder = textures.cache_folder()
    older = folder / "0123.npy"  # as an older raykit kept its decodes
    older.write_bytes(bytes(CACHED_FROM * 4 + 128))
    os.utime(older, (1, 1))
    monkeypatch.setattr(textures, "CACHE_BYTES", CACHED_FROM * 4)
    _large_texture(tmp_path / "t.png", seed=5)
    _texels(tmp_path / "t.png")
    assert not older.exists() and len(_cached_files(tmp_path / "cache")) == 1


def test_in_cache_looks_without_decoding_and_a_decode_after_it_reads_the_file_once(
    tmp_path, monkeypatch
):
    monkeypatch.setenv("RAYKIT_CACHE_DIR", str(tmp_path / "cache"))
    made = _large_texture(tmp_path / "t.png", seed=6)
    texture = Texture(tmp_path / "t.png", "scene.json", "billboards[0].image")
    decodes = _decodes(monkeypatch)
    reads = []
    read_bytes = Path.read_bytes
    monkeypatch.setattr(Path, "read_bytes", lambda self: reads.append(1) or read_bytes(self))
    assert not texture.in_cache() and not texture.decoded and decodes == []
    assert np.array_equal(texture.rgba, made) and decodes == [1] and reads == [1]
    again = Texture(tmp_path / "t.png", "scene.json", "billboards[0].image")
    assert again.in_cache() and again.decoded and decodes == [1]
    small = tmp_path / "small.png"
    Image.new("RGBA", (16, 16)).save(small)
    assert not Texture(small, "scene.json", "billboards[1].image").in_cache()

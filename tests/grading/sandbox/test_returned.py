"""What a test returns, read as hostile input (raykit_grading.sandbox.returned): the archive's
directory bounded before it is parsed, only what numpy writes read."""

from __future__ import annotations

import io
import struct
import time
import tracemalloc
import zipfile

import numpy as np
import pytest

from raykit_grading.sandbox.base import Limits
from raykit_grading.sandbox.returned import read_returned

MB = 2**20


def _archive_of_empty_members(count: int) -> bytes:
    """A zip of ``count`` empty stored members (issue 56's archive had 438,592), as zipfile
    reads one: each member's local header, then the directory of their entries."""
    name = b"m.npy"
    local = struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, 0, 0, 0, 0, 0, 0, len(name), 0) + name
    head = struct.pack("<IHHHHHHIIIHHHHH", 0x02014B50, 20, 20, 0, 0, 0, 0, 0, 0, 0, len(name),
                       0, 0, 0, 0)  # fmt: skip
    entries = np.zeros(count, dtype=[("head", f"S{len(head) + 4}"), ("offset", "<u4"),
                                     ("name", f"S{len(name)}")])  # fmt: skip
    entries["head"], entries["name"] = head + bytes(4), name  # external attributes, then offset
    entries["offset"] = np.arange(count, dtype=np.uint32) * len(local)
    directory = entries.tobytes()
    end = struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, count & 0xFFFF, count & 0xFFFF,
                      len(directory), count * len(local), 0)  # fmt: skip
    return local * count + directory + end


def test_an_archive_of_many_members_is_refused_before_it_is_parsed(monkeypatch):
    """The archive of issue 56: 438,592 empty members, just under 64 MiB, once cost the grader
    80 s and 550 MB; its directory's end is read first, and it is refused before zipfile
    reads any of it, allocating nothing of its size."""
    data = _archive_of_empty_members(438_592)
    assert len(data) < 64 * MB
    assert len(zipfile.ZipFile(io.BytesIO(_archive_of_empty_members(3))).infolist()) == 3
    opened = []
    monkeypatch.setattr(zipfile, "ZipFile", lambda *args, **kwargs: opened.append(args))
    tracemalloc.start()
    with pytest.raises(ValueError, match="more than 16 arrays"):
        read_returned(data, 64 * MB)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert opened == [] and peak < MB, peak
    with pytest.raises(ValueError, match="more than 16 arrays"):
        read_returned(_archive_of_empty_members(17), 64 * MB)
    with pytest.raises(ValueError, match="more than 16777216 bytes"):
        read_returned(data, Limits().returned_bytes)


def test_what_numpy_writes_is_read_and_what_it_never_writes_is_refused():
    good = io.BytesIO()
    np.savez(good, t=np.arange(4.0), s=np.ones((2, 3), np.float32), hit=np.array([True]))
    arrays = read_returned(good.getvalue(), 16 * MB)
    assert arrays["t"].tolist() == [0, 1, 2, 3] and arrays["s"].shape == (2, 3)
    commented = good.getvalue()[:-2] + struct.pack("<H", 4) + b"note"
    with pytest.raises(ValueError, match="no end of its directory last"):
        read_returned(commented, 16 * MB)
    with pytest.raises(TimeoutError):
        read_returned(good.getvalue(), 16 * MB, deadline=time.monotonic() - 1)
    locator = b"PK\x06\x07" + b"\0" * 16
    zip64 = good.getvalue()[:-22] + locator + good.getvalue()[-22:]
    with pytest.raises(ValueError, match="zip64"):
        read_returned(zip64, 16 * MB)


def test_read_returned_refuses_what_is_not_plain_stored_arrays():
    good = io.BytesIO()
    np.savez(good, t=np.arange(4.0))
    assert read_returned(good.getvalue(), 2**20)["t"].tolist() == [0, 1, 2, 3]
    squeezed = io.BytesIO()
    np.savez_compressed(squeezed, t=np.zeros(10))
    for bad in (squeezed.getvalue(), b"PK" + b"\0" * 100, good.getvalue()[:-30]):
        with pytest.raises(ValueError):
            read_returned(bad, 2**20)
    with pytest.raises(ValueError):
        read_returned(good.getvalue(), 10)

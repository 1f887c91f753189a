"""What a child returns, read as hostile input: the ``.npz`` that came over the grader's pipe.

The child (:mod:`raykit_grading.inside.child`) writes its task's arrays with :func:`numpy.savez`;
the grader believes none of it. The archive's directory is bounded from its end before
:mod:`zipfile` parses it, every member must be a stored (not compressed) ``.npy`` of plain
numbers or booleans whose header accounts for exactly the bytes that follow it, and nothing is
inflated or allocated beyond what was sent (``allow_pickle`` never arises: no object array is
made). :class:`raykit_grading.sandbox.base.Limits` sets how many bytes and arrays a test may
return.
"""

from __future__ import annotations

import io
import struct
import time
import zipfile

import numpy as np


def read_returned(
    data: bytes, limit: int, arrays: int = 16, deadline: float | None = None
) -> dict[str, np.ndarray]:
    """The arrays in an ``.npz`` a child returned, read as hostile input.

    Every member must be a stored (uncompressed) ``name.npy`` whose header's shape and dtype
    account for exactly the bytes that follow it, plain numbers or booleans, and all of them
    together at most ``limit`` bytes; so nothing is inflated or allocated beyond what was
    actually sent. The archive's directory is bounded before it is parsed: its end must be
    where numpy writes it (the archive's last 22 bytes), and say at most ``arrays`` members in
    at most :data:`DIRECTORY_BYTES_EACH` bytes each, so parsing it costs the grader nothing
    however many members follow. Raises ValueError saying what is wrong, TimeoutError past
    ``deadline`` (a :func:`time.monotonic` time).
    """
    if len(data) > limit:
        raise ValueError(f"more than {limit} bytes")
    _check_directory(data, arrays)
    try:
        return _read_npz(data, limit, deadline)
    except (ValueError, TimeoutError):
        raise
    except Exception as exc:  # noqa: BLE001 - whatever a hostile archive makes a parser do
        raise ValueError(f"unreadable: {type(exc).__name__}") from None


END_OF_DIRECTORY = struct.Struct("<4s4H2LH")  # a zip's end of central directory record
DIRECTORY_BYTES_EACH = 512  # a member's directory entry: 46 bytes, its name, a zip64 field


def _check_directory(data: bytes, arrays: int) -> None:
    """Refuse an archive whose directory says more than ``arrays`` members, or takes more
    room than they would, before :mod:`zipfile` reads it (which it does whole, on opening)."""
    if len(data) < END_OF_DIRECTORY.size:
        raise ValueError("not an .npz: too short")
    sign, _, _, _, members, size, _, comment = END_OF_DIRECTORY.unpack_from(
        data, len(data) - END_OF_DIRECTORY.size
    )
    if sign != b"PK\x05\x06" or comment:
        raise ValueError("not an .npz as numpy writes one (no end of its directory last)")
    locator = len(data) - END_OF_DIRECTORY.size - 20
    if locator >= 0 and data[locator : locator + 4] == b"PK\x06\x07":
        raise ValueError("a zip64 directory (numpy writes none for a test's arrays)")
    if members > arrays or size > arrays * DIRECTORY_BYTES_EACH:
        raise ValueError(f"more than {arrays} arrays")


def _read_npz(data: bytes, limit: int, deadline: float | None) -> dict[str, np.ndarray]:
    try:
        archive = zipfile.ZipFile(io.BytesIO(data))
    except zipfile.BadZipFile as exc:
        raise ValueError(f"not an .npz: {exc}") from None
    arrays = {}
    with archive:
        members = archive.infolist()
        if sum(m.file_size for m in members) > limit:
            raise ValueError("its arrays are larger than allowed")
        for member in members:
            if deadline is not None and time.monotonic() > deadline:
                raise TimeoutError
            if (
                member.compress_type != zipfile.ZIP_STORED
                or member.file_size != member.compress_size
            ):
                raise ValueError(f"{member.filename} is compressed")
            if not member.filename.endswith(".npy"):
                raise ValueError(f"{member.filename} is not an array")
            with archive.open(member) as stream:
                version = np.lib.format.read_magic(stream)
                read_header = {
                    (1, 0): np.lib.format.read_array_header_1_0,
                    (2, 0): np.lib.format.read_array_header_2_0,
                }.get(version)
                if read_header is None:
                    raise ValueError(f"{member.filename}: .npy version {version}")
                shape, fortran, dtype = read_header(stream)
                if dtype.kind not in "biuf" or dtype.hasobject:
                    raise ValueError(f"{member.filename}: values of type {dtype}")
                size = int(np.prod(shape, dtype=np.int64)) * dtype.itemsize
                if stream.tell() + size != member.file_size:
                    raise ValueError(f"{member.filename}: its header does not match its size")
                array = np.frombuffer(stream.read(size), dtype=dtype)
                array = array.reshape(shape, order="F" if fortran else "C")
            arrays[member.filename[: -len(".npy")]] = array
    if deadline is not None and time.monotonic() > deadline:
        raise TimeoutError
    return arrays

"""What the child hands back is read as untrusted (3)."""

from __future__ import annotations

import pytest

from hostile.deployed import (
    everything_visible,
    grade_as_deployed,
    scores,
    submission_with,
)

pytestmark = pytest.mark.slow


# ---- 3: what the child hands back is read as untrusted -------------------------------------

RETURNED = {
    "a compressed npz (a bomb)": (
        "import io, zipfile\n"
        "buf = io.BytesIO()\n"
        "with zipfile.ZipFile(buf, 'w', zipfile.ZIP_DEFLATED) as z:\n"
        "    z.writestr('t.npy', b'\\x93NUMPY\\x01\\x00v\\x00' + b' ' * 118 + b'\\n'"
        " + b'\\0' * 50_000_000)\n"
        "data = buf.getvalue()"
    ),
    "a header that claims a huge array": (
        "import io, zipfile\n"
        "header = \"{{'descr': '<f8', 'fortran_order': False, 'shape': (10**12,), }}\"\n"
        "header = header.ljust(117) + '\\n'\n"
        "npy = b'\\x93NUMPY\\x01\\x00' + len(header).to_bytes(2, 'little') + header.encode()\n"
        "buf = io.BytesIO()\n"
        "with zipfile.ZipFile(buf, 'w') as z:\n"
        "    z.writestr('t.npy', npy + b'\\0' * 64)\n"
        "data = buf.getvalue()"
    ),
    "object arrays (pickles)": (
        "import io, numpy\nbuf = io.BytesIO()\n"
        "numpy.savez(buf, t=numpy.array([object()], dtype=object))\ndata = buf.getvalue()"
    ),
    "garbage": "data = b'PK' + b'\\xff' * 5000",
    "endless bytes": "data = b'x' * (200 * 2**20)",
}


@pytest.mark.parametrize("name", sorted(RETURNED))
def test_3_what_a_child_returns_is_checked_before_it_is_believed(
    name, release, autograder, tmp_path
):
    """The child writes its own 'results' to the grader's pipe (task.json names it) and exits
    before child.py can."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import json, os, sys\n"
        + "".join(f"    {line}\n" for line in RETURNED[name].splitlines())
        + "    order = json.load(open(os.path.join(sys.argv[1], 'task.json')))\n"
        "    out = open(order['outputs_fd'], 'wb', closefd=False)\n"
        "    out.write(data)\n    out.flush()\n    os._exit(0)"
    )
    submission = submission_with(release, tmp_path, {"planes.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.1", "2.3"], tmp_path)
    assert scores(results) == {"2.1": 0, "2.3": 2}, results
    assert run.returncode == 0, run.stderr[-2000:]


def test_3_the_sandbox_gives_the_child_no_writable_path_the_grader_reads(
    release, autograder, tmp_path
):
    """It tries to swap every file of its work folder for a link to a root-only file or a
    FIFO: the folder is read-only, and the grader reads nothing back from it anyway."""
    code = (
        "def hit_plane(origins, directions, a, n):\n    import os, numpy as np\n"
        "    swapped = 0\n"
        "    for name in os.listdir('/work'):\n"
        "        try:\n"
        "            os.replace('/work/' + name, '/tmp/x'); swapped += 1\n"
        "        except OSError:\n            pass\n"
        "        try:\n"
        "            os.mkfifo('/work/' + name + '.fifo'); swapped += 1\n"
        "        except OSError:\n            pass\n"
        "    return np.full(len(origins), np.inf) if swapped == 0 else 1 / 0"
    )
    submission = submission_with(release, tmp_path, {"planes.py": code})
    results, run = grade_as_deployed(autograder, submission, ["2.1"], tmp_path)
    assert "division by zero" not in everything_visible(results)
    assert scores(results) == {"2.1": 0}

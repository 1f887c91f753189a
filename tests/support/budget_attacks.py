"""Submissions that try to hold more than a test's budgets, or to learn a hidden test's outcome
from what is shown at once (issue 56's findings), each written into one student function so that
one graded submission carries them all and each test's score is still exact.

Each entry of :data:`ATTACKS`: the module, the function it replaces (the original is kept as
``_function`` and called when the attack wants the right answer, as
``hostile.deployed.submission_wrapping`` lays it out), and the code. An attack that needs
something the sandbox must refuse answers right only if it was refused, so a defence that
failed shows as a lower score; one that must be stopped holds what it can until it is, so a
budget that was not enforced shows as the test's time running out instead of the budget's
message, which the tests assert: nothing depends on when the grader looks.

* ``nameless disk`` (2.1, visible): files with no name, through ``O_TMPFILE`` and, when that is
  refused, files unlinked while open; held by descriptors, fsynced, kept until it is stopped.
* ``kernel buffers`` (2.6, visible): socket pairs and pipes filled (pipes enlarged first), by the
  test's process and three forks; right only if they all held less than 64 MB.
* ``hidden outcomes`` (2.3 visible, 2.4 and 2.5 hidden): the hidden tests fail, the visible
  one passes; what is shown at once must be what an honest submission shows.
* ``memory across processes`` (2.7, visible): fifteen children of 45 MB each, every one under
  its own limit; right only if no child could hold any.
* ``page tables`` (4.1, visible): 20,000 mappings of two pages, each across a gigabyte
  boundary: 320 MB of page tables, which the address-space limit does not count, beside
  160 MB of memory; past the budget where a container leaves a test less than 480 MB
  (Gradescope's: then held until it is stopped), within it elsewhere (then let be).
* ``archive of empty members`` (4.2, visible): returns an ``.npz`` of empty members as large
  as it may send (15 MB, 100,000 members), which the grader must refuse without parsing it.
"""

from __future__ import annotations

from pathlib import Path

from mistaken_submissions import make_submission

NAMELESS_DISK = """
def hit_plane(origins, directions, a, n):
    import os, tempfile, time
    home, held, how = os.environ['HOME'], [], set()
    block = b'x' * 2**20
    for _ in range(6):
        try:
            fd = os.open(home, os.O_TMPFILE | os.O_RDWR, 0o600)
            how.add('O_TMPFILE')
        except OSError as e:
            how.add(f'O_TMPFILE refused ({e.errno}), unlinked instead')
            fd, name = tempfile.mkstemp(dir=home)
            os.unlink(name)  # open, with no name
        for _ in range(40):
            os.write(fd, block)
        os.fsync(fd)
        held.append(fd)
    print('HELD', sorted(how), sum(os.fstat(fd).st_blocks for fd in held) >> 11, 'MB')
    time.sleep(30)  # held until the grader stops it: past its time, the test says so instead
    return _hit_plane(origins, directions, a, n)
"""

KERNEL_BUFFERS = """
def plane_side(p, a, n):
    import fcntl, os, socket, time
    chunk = b'x' * 2**16

    def fill(fd, most):
        os.set_blocking(fd, False)
        written = 0
        try:
            while written < most:
                written += os.write(fd, chunk)
        except (BlockingIOError, BrokenPipeError):
            pass
        return written

    def hold(said):
        held, keep = 0, []
        try:
            for _ in range(6):
                pair = socket.socketpair()
                keep.append(pair)
                for end in pair:
                    end.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 2**23)
                    held += fill(end.fileno(), 2**23)
        except OSError as e:
            said.append(f'socketpair {e.errno}')
        try:
            for _ in range(12):
                r, w = os.pipe()
                keep.append((r, w))
                try:
                    fcntl.fcntl(w, 1031, 2**20)  # F_SETPIPE_SZ
                except OSError as e:
                    said.append(f'F_SETPIPE_SZ {e.errno}')
                held += fill(w, 2**21)
        except OSError as e:
            said.append(f'pipe {e.errno}')
        return held, keep

    said, total, children = [], 0, []
    for _ in range(3):
        try:
            report_r, report_w = os.pipe()
            pid = os.fork()
        except OSError as e:
            said.append(f'fork {e.errno}')
            break
        if pid == 0:
            held, keep = hold([])
            os.write(report_w, str(held).encode())
            time.sleep(30)
            os._exit(0)
        children.append(report_r)
    held, keep = hold(said)
    total += held
    for r in children:
        total += int(os.read(r, 20) or 0)
    print('KERNEL', sorted(set(said)), 'held', total >> 20, 'MB')
    right = _plane_side(p, a, n)
    return right if total < 64 * 2**20 else -right
"""

HIDDEN_OUTCOMES = """
def hit_sphere(origins, directions, center, radius):
    if len(origins) < 500:  # 2.4 and 2.5, the hidden ones, draw fewer rays than 2.3
        raise ValueError('a hidden test')
    return _hit_sphere(origins, directions, center, radius)
"""

MEMORY_ACROSS_PROCESSES = """
def normal_from_points(a, p, q):
    import os, time
    said, held, children = [], 0, []
    for _ in range(15):
        try:
            ready_r, ready_w = os.pipe()
            pid = os.fork()
        except OSError as e:
            said.append(f'fork {e.errno}')
            break
        if pid == 0:
            hog = bytearray(45 * 2**20)  # every page written: held, under its own limit
            os.write(ready_w, b'1')
            time.sleep(30)
            os._exit(0)
        children.append(ready_r)
    for r in children:
        if os.read(r, 1) == b'1':
            held += 45 * 2**20
    print('PROCESSES', sorted(set(said)), 'children held', held >> 20, 'MB')
    right = _normal_from_points(a, p, q)
    return right if held == 0 else -right
"""

PAGE_TABLES = """
def sphere_normals(points, center, radius):
    import ctypes, resource, time
    libc = ctypes.CDLL(None, use_errno=True)
    libc.mmap.restype = ctypes.c_void_p
    libc.mmap.argtypes = [ctypes.c_void_p, ctypes.c_size_t, ctypes.c_int, ctypes.c_int,
                          ctypes.c_int, ctypes.c_long]
    fixed_noreplace_populate = 0x22 | 0x100000 | 0x8000
    made = 0
    for i in range(20000):  # two pages across a gigabyte boundary: 4 page-table pages each
        address = libc.mmap(0x100000000000 + (i << 30) - 4096, 8192, 3,
                            fixed_noreplace_populate, -1, 0)
        if address is None or address >= 2**64 - 4096:
            break
        made += 1
    print('MAPPINGS', made)
    if made * (8192 + 4 * 4096) > resource.getrlimit(resource.RLIMIT_AS)[0]:
        time.sleep(30)  # past its memory budget (M): held until the grader stops it
    time.sleep(0.3)  # within it: looked at, and let be
    return _sphere_normals(points, center, radius)
"""

ARCHIVE_OF_EMPTY_MEMBERS = """
def toward_light(light, points):
    import os, struct
    import json, sys
    local, central = [], []
    offset, size, count = 0, 22, 0
    while size < 15 * 2**20:  # each member's local header and its directory entry
        name = f'm{count}.npy'.encode()
        header = struct.pack('<IHHHHHIIIHH', 0x04034B50, 20, 0, 0, 0, 0, 0, 0, 0, len(name), 0)
        central.append(struct.pack('<IHHHHHHIIIHHHHHII', 0x02014B50, 20, 20, 0, 0, 0, 0, 0,
                                   0, 0, len(name), 0, 0, 0, 0, 0, offset) + name)
        local.append(header + name)
        offset += len(header) + len(name)
        size += 2 * len(name) + 76
        count += 1
    directory = b''.join(central)
    end = struct.pack('<IHHHHIIH', 0x06054B50, 0, 0, count & 0xFFFF, count & 0xFFFF,
                      len(directory), offset, 0)
    data = b''.join(local) + directory + end
    print('MEMBERS', count, len(data) >> 20, 'MB')
    order = json.load(open(os.path.join(sys.argv[1], 'task.json')))  # the grader's pipe
    out = open(order['outputs_fd'], 'wb', closefd=False)
    out.write(data)
    out.flush()
    os._exit(0)
"""

ATTACKS = {
    "nameless disk": ("planes.py", "hit_plane", NAMELESS_DISK),
    "kernel buffers": ("planes.py", "plane_side", KERNEL_BUFFERS),
    "hidden outcomes": ("spheres.py", "hit_sphere", HIDDEN_OUTCOMES),
    "memory across processes": ("planes.py", "normal_from_points", MEMORY_ACROSS_PROCESSES),
    "page tables": ("spheres.py", "sphere_normals", PAGE_TABLES),
    "archive of empty members": ("lights.py", "toward_light", ARCHIVE_OF_EMPTY_MEMBERS),
}


def budget_attacker(folder: Path, names: tuple[str, ...] = tuple(ATTACKS)) -> Path:
    """The solution with the attacks ``names`` written in (each function renamed ``_name``,
    the attack defined after it)."""
    make_submission(folder)
    for name in names:
        module, function, code = ATTACKS[name]
        path = folder / "raykit" / module
        text = path.read_text()
        assert text.count(f"def {function}(") == 1, (module, function)
        path.write_text(text.replace(f"def {function}(", f"def _{function}(", 1) + code)
    return folder

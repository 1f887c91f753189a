"""A page as a reader's browser shows it, with no network: a folder served from this machine and
opened in headless Chromium, which runs a measuring page's script and hands back what it wrote
into ``<pre id="result">`` (tests/test_site.py, tests/test_deck.py)."""

from __future__ import annotations

import contextlib
import functools
import html
import http.server
import json
import re
import shutil
import subprocess
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path

CHROMIUM = next(
    (shutil.which(n) for n in ("chromium", "chromium-browser", "google-chrome") if shutil.which(n)),
    None,
)


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@contextlib.contextmanager
def served(folder: Path) -> Iterator[str]:
    """``folder`` served on 127.0.0.1 while the block runs; yields its address."""
    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(_Quiet, directory=str(folder))
    )
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


def measured(url: str, window: tuple[int, int]) -> object:
    """Open ``url`` (a measuring page) in headless Chromium with a window of ``window`` pixels,
    every name but this machine's unknown to it; the JSON its script wrote as its result."""
    with tempfile.TemporaryDirectory() as profile:
        dump = subprocess.run(
            [
                CHROMIUM,
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--disable-quic",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                f"--user-data-dir={profile}",
                # no network: every name but this machine's is unknown
                "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
                "--hide-scrollbars",
                "--virtual-time-budget=6000000",
                f"--window-size={window[0]},{window[1]}",
                "--dump-dom",
                url,
            ],
            capture_output=True,
            text=True,
            timeout=900,
            check=False,
        ).stdout
    found = re.search(r'<pre id="result">(.*?)</pre>', dump, re.S)
    assert found and found.group(1) != "running", "the measuring page did not finish"
    return json.loads(html.unescape(found.group(1)))

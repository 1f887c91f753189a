"""The documentation site as a reader's browser shows it, with no network (a lecture room, a
train): built as CI builds it, served from this machine, and measured page by page in headless
Chromium at a phone's width (400 px) and a laptop's (1280 px).

* Nothing a page needs comes from another site: its scripts, styles, fonts and pictures (and so
  MathJax) are the site's own, and every formula is typeset.
* No page scrolls sideways as a whole, and no part of a page is cut: every element (its box, or
  the text it holds) lies inside the window and inside each ancestor that hides what overflows
  it, unless a block between them scrolls sideways on its own (a code block, a table's
  scroller, a notebook output). The article's own frame does not count as such a block: a
  line wider than the text moves the whole text. Nor do the side columns ("Section
  Navigation", "On this page"): nothing in them is wider than the column.
* No table is squeezed into the page when it could scroll in its own block instead: no word in
  a cell is broken across two lines (raykit.line|scan), and no short phrase in a cell ("5.9 ms",
  a header) is set one word a line.
* ``tests/site_measure.html`` measures it all, every page at both widths in one Chromium.
* No page has an empty left column ("Section Navigation" with nothing under it).

The site is built once for the module, with the docs extra (skipped, saying so, without it);
the browser tests are skipped, saying so, where Chromium is not installed.
"""

from __future__ import annotations

import functools
import html
import http.server
import importlib.util
import json
import re
import shutil
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import pytest

from conftest import REPO

HERE = Path(__file__).resolve().parent
WIDTHS = (400, 1280)
CHROMIUM = next(
    (
        shutil.which(name)
        for name in ("chromium", "chromium-browser", "google-chrome")
        if shutil.which(name)
    ),
    None,
)
DOCS_EXTRA = ("sphinx", "myst_nb", "pydata_sphinx_theme", "sphinx-mathjax-offline")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    missing = [name for name in DOCS_EXTRA if importlib.util.find_spec(name) is None]
    if missing:
        pytest.skip(
            f'the site needs the docs extra ({", ".join(missing)}): pip install -e ".[docs]"'
        )
    out = tmp_path_factory.mktemp("site")
    subprocess.run(
        [
            sys.executable,
            "-m",
            "sphinx",
            "-W",
            "--keep-going",
            "-q",
            "-b",
            "html",
            "docs",
            str(out),
        ],
        cwd=REPO,
        check=True,
    )
    return out


def _pages(site: Path) -> list[str]:
    return sorted(
        str(path.relative_to(site))
        for path in site.rglob("*.html")
        if not path.relative_to(site).parts[0].startswith(("_", "."))
    )


ASSET = re.compile(
    r"<(?:script|img|source|iframe)\b[^>]*\bsrc=\"([^\"]+)\"|<link\b[^>]*\bhref=\"([^\"]+)\"", re.I
)
CSS_URL = re.compile(r"url\(\s*['\"]?(https?:|//)", re.I)


def test_no_page_loads_anything_from_another_site(site):
    outside = {}
    for page in _pages(site):
        for match in ASSET.finditer((site / page).read_text(encoding="utf-8")):
            url = match.group(1) or match.group(2)
            tag = match.group(0)
            if match.group(2) and not re.search(
                r"rel=\"(stylesheet|preload|icon|modulepreload)", tag
            ):
                continue  # a link to another page, not something the page loads
            if url.startswith(("http:", "https:", "//")):
                outside.setdefault(url, []).append(page)
    for css in site.glob("_static/**/*.css"):
        if CSS_URL.search(css.read_text(encoding="utf-8", errors="replace")):
            outside.setdefault(f"url() in {css.relative_to(site)}", []).append("")
    assert not outside, outside
    assert (site / "_static" / "mathjax" / "tex-chtml.js").is_file()


def test_no_page_has_an_empty_section_navigation_column(site):
    empty = []
    for page in _pages(site):
        text = (site / page).read_text(encoding="utf-8")
        start = text.find('id="pst-primary-sidebar"')
        column = text[start : text.find("<main", start)]
        if "Section Navigation" in column and 'class="reference internal' not in column:
            empty.append(page)
    assert not empty


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def served(site):
    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(_Quiet, directory=str(site))
    )
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


@pytest.fixture(scope="module")
def measured(site, served) -> dict[int, list[dict]]:
    """Every page at every width of WIDTHS, measured by ``site_measure.html`` in one Chromium."""
    if CHROMIUM is None:
        pytest.skip("needs Chromium (apt-get install chromium)")
    pages = _pages(site)
    page = (HERE / "site_measure.html").read_text()
    page = page.replace("/*PAGES*/[]", json.dumps(pages))
    page = page.replace("/*WIDTHS*/[]", json.dumps(WIDTHS))
    (site / "_measure.html").write_text(page)
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
                f"--window-size={max(WIDTHS) + 100},1000",
                "--dump-dom",
                f"{served}/_measure.html",
            ],
            capture_output=True,
            text=True,
            timeout=900,
            check=False,
        ).stdout
    found = re.search(r'<pre id="result">(.*?)</pre>', dump, re.S)
    assert found and found.group(1) != "running", "the measuring page did not finish"
    results = json.loads(html.unescape(found.group(1)))
    assert len(results) == len(pages) * len(WIDTHS)
    return {width: [r for r in results if r["width"] == width] for width in WIDTHS}


@pytest.mark.parametrize("width", WIDTHS)
def test_every_page_fits_the_window_with_nothing_cut_and_its_formulas_typeset(measured, width):
    results = measured[width]
    errors = {r["page"]: r["error"] for r in results if "error" in r}
    assert not errors
    wide = {r["page"]: r["scrollWidth"] for r in results if r["scrollWidth"] > r["width"]}
    assert not wide, f"pages wider than the {width}-px window: {wide}"
    cut = {r["page"]: r["cut"][:3] for r in results if r["cut"]}
    assert not cut, f"cut at {width} px: {json.dumps(cut, indent=1, ensure_ascii=False)}"
    raw = {r["page"]: r["math_unrendered"] for r in results if r["math_unrendered"]}
    assert not raw, f"formulas left as TeX source: {raw}"


@pytest.mark.parametrize("width", WIDTHS)
def test_no_table_is_squeezed_into_the_page_breaking_its_words(measured, width):
    squeezed = {r["page"]: r["tables"][:3] for r in measured[width] if r.get("tables")}
    assert not squeezed, (
        f"tables squeezed at {width} px: {json.dumps(squeezed, indent=1, ensure_ascii=False)}"
    )

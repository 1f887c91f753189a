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
* No page name in the footer's "previous" and "next" links or in the left column ("Section
  Navigation") is broken inside a word ("Benchma|rks", "raykit.engine.compile|d.billboards",
  "compiled.billbo|ards"): a dotted name breaks after a dot.
* Nor is a word in a page's title ("raykit.engine.compiled.bil|lboards"), in its headings
  (SHADOW_CANDIDATES) or in an API entry's signature (a parameter "b|oard"): a name breaks after
  a dot, a signature also between its parameters. In the right column ("On this page") only a
  word wider than the column may be broken ("grade_in_prairielearn_container()").
* No inline formula has a scroll bar of its own; a display formula wider than the column may.
* ``tests/site_measure.html`` measures it all, every page at both widths in one Chromium.
* No page has an empty left column ("Section Navigation" with nothing under it).

The site is built once for the module, with the docs extra (skipped, saying so, without it),
or taken from the folder ``RAYKIT_SITE`` names, where .ci/run has just built it with the same
command; the browser tests are skipped, saying so, where Chromium is not installed.
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import headless
from conftest import REPO
from headless import CHROMIUM, served

HERE = Path(__file__).resolve().parent
WIDTHS = (400, 1280)
DOCS_EXTRA = ("sphinx", "myst_nb", "pydata_sphinx_theme", "sphinx-mathjax-offline")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    missing = [name for name in DOCS_EXTRA if importlib.util.find_spec(name) is None]
    if missing:
        pytest.skip(
            f'the site needs the docs extra ({", ".join(missing)}): pip install -e ".[docs]"'
        )
    built = os.environ.get("RAYKIT_SITE")
    if built:  # .ci/run has just built it, with the command below
        return Path(built).resolve()
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
    """The site's pages, and the deck's (docs/make_deck.py, deck/index.html)."""
    return sorted(
        str(path.relative_to(site))
        for path in site.rglob("*.html")
        if not path.relative_to(site).parts[0].startswith(("_", "."))
    )


def _measured_pages(site: Path) -> list[str]:
    """The pages measured at a phone's and a laptop's width: not the deck, which is a
    projector's 1920 x 1080 (tests/test_deck.py measures it)."""
    return [page for page in _pages(site) if not page.startswith("deck/")]


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


@pytest.fixture(scope="module")
def measured(site) -> dict[int, list[dict]]:
    """Every page at every width of WIDTHS, measured by ``site_measure.html`` in one Chromium."""
    if CHROMIUM is None:
        pytest.skip("needs Chromium (apt-get install chromium)")
    pages = _measured_pages(site)
    page = (HERE / "site_measure.html").read_text()
    page = page.replace("/*PAGES*/[]", json.dumps(pages))
    page = page.replace("/*WIDTHS*/[]", json.dumps(WIDTHS))
    (site / "_measure.html").write_text(page)
    with served(site) as address:
        results = headless.measured(f"{address}/_measure.html", (max(WIDTHS) + 100, 1000))
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


@pytest.mark.parametrize("width", WIDTHS)
def test_no_footer_link_or_left_column_breaks_a_page_name_inside_a_word(measured, width):
    broken = {r["page"]: r["broken"][:3] for r in measured[width] if r.get("broken")}
    assert not broken, f"at {width} px: {json.dumps(broken, indent=1, ensure_ascii=False)}"


@pytest.mark.parametrize("width", WIDTHS)
def test_no_heading_or_signature_breaks_a_word_inside(measured, width):
    broken = {r["page"]: r["headings"][:3] for r in measured[width] if r.get("headings")}
    assert not broken, f"at {width} px: {json.dumps(broken, indent=1, ensure_ascii=False)}"


@pytest.mark.parametrize("width", WIDTHS)
def test_no_entry_of_on_this_page_breaks_a_word_that_fits_on_a_line(measured, width):
    broken = {r["page"]: r["contents"][:3] for r in measured[width] if r.get("contents")}
    assert not broken, f"at {width} px: {json.dumps(broken, indent=1, ensure_ascii=False)}"


@pytest.mark.parametrize("width", WIDTHS)
def test_no_inline_formula_has_a_scroll_bar_of_its_own(measured, width):
    scrolling = {r["page"]: r["math_scrolls"][:3] for r in measured[width] if r["math_scrolls"]}
    assert not scrolling, f"at {width} px: {json.dumps(scrolling, indent=1, ensure_ascii=False)}"


def test_the_notebooks_sliders_move_through_their_functions_pictures(site, measured):
    """Every slider cell of the notebooks is on the site as sliders (docs/conf.py); moving each
    control shows, and loads, the picture docs/make_slider_frames.py drew for that stop."""
    expected = {}
    for manifest in sorted((site / "_static" / "sliders").glob("*/*/sliders.json")):
        data = json.loads(manifest.read_text())
        folder = f"../_static/sliders/{manifest.parent.parent.name}/{manifest.parent.name}/"
        page = f"notebooks/{manifest.parent.parent.name}.html"
        for control in data["controls"]:
            last = len(control["labels"]) - 1
            stop = 0 if control["first"] == last else last
            expected.setdefault(page, []).append(
                (control["name"], stop, folder + control["frames"][stop])
            )
    assert {"notebooks/01_rays_and_cameras.html", "notebooks/02_linescan_camera.html"} <= set(
        expected
    )
    shown = {
        r["page"]: [(m["control"], m["stop"], m["after"]) for m in r["sliders"]]
        for r in measured[WIDTHS[-1]]
        if r.get("sliders")
    }
    assert shown == expected
    unloaded = [(r["page"], m) for r in measured[WIDTHS[-1]] for m in r.get("sliders", [])]
    assert not [u for u in unloaded if not u[1]["loaded"]]
    # each control really changes the picture (a slider whose every stop draws the same
    # figure would show nothing moving)
    assert all(m["after"] != m["before"] for _, m in unloaded)

"""The lecture as a slide deck (docs/make_deck.py): one slide per entry of notebooks/lecture.json,
in its order, with the slide's words, its figure and the figure's code; shown at a projector's
1920 x 1080 in headless Chromium with no network, every slide fits the screen with nothing cut,
its formulas typeset and its pictures loaded, and nothing is asked of another machine.

Needs the docs extra (reveal.js comes from sphinx-revealjs, MathJax from sphinx-mathjax-offline)
and, for the browser test, Chromium; each test says so when it skips.
"""

from __future__ import annotations

import html
import importlib.util
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import headless
from conftest import REPO
from headless import CHROMIUM, served
from raykit.io.legibility import SMALLEST_SCREEN_TEXT

HERE = Path(__file__).resolve().parent
LECTURE = REPO / "notebooks" / "lecture.json"


def _maker():
    spec = importlib.util.spec_from_file_location("make_deck", REPO / "docs" / "make_deck.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


MAKER = _maker()


@pytest.fixture(scope="module")
def deck(tmp_path_factory) -> Path:
    for package in ("sphinx_revealjs", "sphinx-mathjax-offline", "pygments"):
        if importlib.util.find_spec(package) is None:
            pytest.skip(f'the deck needs the docs extra ({package}): pip install -e ".[docs]"')
    out = tmp_path_factory.mktemp("deck") / "deck"
    MAKER.build(out)
    return out


def _sections(index: Path) -> list[str]:
    return re.findall(r"<section\b.*?</section>", index.read_text(encoding="utf-8"), re.S)


def test_one_slide_per_lecture_slide_in_order_with_its_words_figure_and_code(deck):
    slides = json.loads(LECTURE.read_text(encoding="utf-8"))["slides"]
    sections = _sections(deck / "index.html")
    assert len(sections) == len(slides)
    for slide, section in zip(slides, sections, strict=True):
        title = re.search(r"<h2>(.*?)</h2>", section, re.S).group(1)
        assert html.unescape(title) == slide["title"]
        # the words as the slide shows them, spaces aside (a data sheet's tabs are a table's cells)
        text = re.sub(r"\s", "", html.unescape(re.sub(r"<[^>]+>|\\\(|\\\)", "", section)))
        for quote in slide["quotes"]:  # **bold** as bold, but not where set as written
            words = re.sub(r"\s", "", quote.replace("**", "").removeprefix("- "))
            assert words in text or re.sub(r"\s", "", quote) in text, (slide["title"], quote)
        pictures = re.findall(r'<img src="(figures/[^"]+)"', section)
        if slide.get("figure"):
            assert len(pictures) == 1 and (deck / pictures[0]).is_file(), slide["title"]
            assert "<details>" in section
            assert re.sub(r"\s", "", slide["figure"]) in text
        elif slide.get("image"):  # the stored picture a Markdown cell shows, and its path
            stored = (REPO / "notebooks" / slide["image"]).resolve()
            assert len(pictures) == 1, slide["title"]
            assert (deck / pictures[0]).read_bytes() == stored.read_bytes(), slide["title"]
            assert "<details>" not in section
            assert str(stored.relative_to(REPO)) in text
        else:
            assert not pictures
        assert re.search(r'<a href="\.\./notebooks/' + re.escape(slide["notebook"][:-6]), section)


def _as_written(slide: dict) -> list[str]:
    """The slide's quotes its notebook sets in a fenced block (a data sheet's table aside)."""
    cells = json.loads((REPO / "notebooks" / slide["notebook"]).read_text())["cells"]
    fenced = MAKER.fenced_blocks(cells)
    return [q for q in slide["quotes"] if MAKER.set_as_written(q, fenced) and "\t" not in q]


def test_a_quote_its_notebook_sets_as_written_is_shown_as_written_as_on_the_site(deck):
    """The pseudo-code, and the slides whose TeX the lecture's text writes outside dollar
    signs ("Let \\mathbf{u}, \\mathbf{v} be orthonormal ..."): the notebooks set them in fenced
    blocks, which the site shows as written, TeX and all; the deck shows the same."""
    slides = json.loads(LECTURE.read_text(encoding="utf-8"))["slides"]
    sections = _sections(deck / "index.html")
    kept = {k: _as_written(slide) for k, slide in enumerate(slides)}
    assert sum(q.startswith("Let \\mathbf{u}") for quotes in kept.values() for q in quotes) == 1
    assert sum(len(quotes) for quotes in kept.values()) >= 8  # six loops, three slides of TeX
    for k, quotes in kept.items():
        for quote in quotes:
            block = f"<code>{html.escape(quote.strip(chr(10)))}</code></pre>"
            shown = re.search(r'<pre class="as-written[ \w-]*">' + re.escape(block), sections[k])
            assert shown, (slides[k]["title"], quote[:60])
    # TeX outside dollar signs appears in no quote shown as prose: MathJax would leave it raw
    for k, slide in enumerate(slides):
        for quote in slide["quotes"]:
            prose = "".join(MAKER.MATH.split(quote)[::2])
            assert quote in kept[k] or not re.search(r"\\[a-zA-Z]+\{", prose), quote[:60]


def test_every_link_to_a_notebook_names_a_section_the_notebook_opens(deck):
    """The deck links each slide to its section on the site: the anchor is the id docutils
    gives the heading (the site's build, tests/test_site.py, shows the same ids)."""
    for section in _sections(deck / "index.html"):
        link = re.search(r'<a href="\.\./notebooks/([\w.]+)\.html#([\w-]+)"', section)
        assert link, section[:200]
        cells = json.loads((REPO / "notebooks" / f"{link.group(1)}.ipynb").read_text())["cells"]
        headings = [
            line
            for c in cells
            if c["cell_type"] == "markdown"
            for line in "".join(c["source"]).splitlines()
            if line.startswith("#")
        ]
        ids = {MAKER.section_anchor(cells, h, "") for h in headings}
        assert link.group(2) in ids


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda d: d["slides"][3].update(figure="no cell has this"), r"slides\[3\].*\.figure: 0"),
        (lambda d: d["slides"][0].pop("title"), r"slides\[0\]\.title: must be a str"),
        (lambda d: d["slides"][2].update(cell="## not a heading here"), r"slides\[2\].*\.cell"),
        (lambda d: d["slides"][1].update(notebook="99_none.ipynb"), r"slides\[1\].*notebook"),
        (lambda d: d["slides"][5].update(image="../none.png"), r"slides\[5\].*\.image: no such"),
        (lambda d: d["slides"][5].update(figure="x"), r"slides\[5\]\.image: a slide has a figure"),
    ],
)
def test_a_bad_lecture_json_is_one_line_naming_the_field_and_writes_nothing(
    tmp_path, change, message
):
    pytest.importorskip(
        "sphinx_revealjs", reason='the deck needs the docs extra: pip install -e ".[docs]"'
    )
    data = json.loads(LECTURE.read_text(encoding="utf-8"))
    change(data)
    bad = tmp_path / "lecture.json"
    bad.write_text(json.dumps(data))
    command = [
        sys.executable,
        "docs/make_deck.py",
        "-o",
        str(tmp_path / "deck"),
        "--lecture",
        str(bad),
    ]
    done = subprocess.run(command, cwd=REPO, capture_output=True, text=True, check=False)
    assert done.returncode == 1 and done.stdout == ""
    assert len(done.stderr.strip().splitlines()) == 1 and "Traceback" not in done.stderr
    assert re.search(message, done.stderr), done.stderr
    assert not (tmp_path / "deck").exists()


@pytest.mark.skipif(CHROMIUM is None, reason="needs Chromium (apt-get install chromium)")
def test_every_slide_fits_a_1920_by_1080_screen_offline(deck):
    shutil.copy(HERE / "deck_measure.html", deck.parent / "measure.html")
    with served(deck.parent) as origin:
        result = headless.measured(f"{origin}/measure.html", (1920, 1200))
    assert "error" not in result, result
    slides = json.loads(LECTURE.read_text(encoding="utf-8"))["slides"]
    assert [s["title"] for s in result["slides"]] == [s["title"] for s in slides]
    cut = {f"{s['index']} {s['title']}": s["cut"][:3] for s in result["slides"] if s["cut"]}
    assert not cut, json.dumps(cut, indent=1, ensure_ascii=False)
    # every text at least 1/40 of the screen's height (the projector rule), the folded code
    # opened too, on the screen
    smallest = SMALLEST_SCREEN_TEXT - 0.05
    small = {
        f"{s['index']} {s['title']}": [t for t in s["smallest"] if t["px"] < smallest]
        for s in result["slides"]
    }
    small = {slide: texts for slide, texts in small.items() if texts}
    assert not small, json.dumps(small, indent=1, ensure_ascii=False)
    assert all(s["texts"] >= 2 for s in result["slides"])  # a title and a link, at least
    folded = [s for s in result["slides"] if s["code"] is not None]
    assert [s["index"] for s in folded] == [k for k, s in enumerate(slides) if s.get("figure")]
    for slide in folded:
        assert slide["code"]["texts"] >= 2 and not slide["code"]["cut"], slide
        assert all(t["px"] >= smallest for t in slide["code"]["smallest"]), slide
    # the formulas are typeset, the pictures and the quotes set as written are there
    written = [_as_written(s) for s in slides]
    formulas = sum(
        len(MAKER.MATH.findall(q))
        for s, kept in zip(slides, written, strict=True)
        for q in s["quotes"]
        if q not in kept
    )
    assert sum(s["formulas"] for s in result["slides"]) >= formulas > 0
    shown = [int(bool(s.get("figure") or s.get("image"))) for s in slides]
    assert [s["pictures"] for s in result["slides"]] == shown
    assert [s["code_blocks"] for s in result["slides"]] == [len(kept) for kept in written]
    # everything came from the deck's own folder, and came
    away = [r for r in result["requests"] if not r["url"].startswith(origin + "/")]
    assert not away, away
    failed = [r for r in result["requests"] if r["status"] not in (200, 304)]
    assert not failed, failed

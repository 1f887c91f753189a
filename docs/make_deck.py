"""The lecture as a slide deck, made from the notebooks: one slide per slide of the lecture.

    python docs/make_deck.py [-o OUT_FOLDER] [--notebooks URL]

Reads ``notebooks/lecture.json`` (the lecture's slides in order, each with the words the kit
quotes from it, the notebook section that teaches it and the code cell that draws its figure)
and writes OUT_FOLDER/index.html (default: docs/_build/deck), a reveal.js deck that needs no
network: each slide's title and its text word for word (formulas typeset by MathJax,
pseudo-code as code), the figure that cell of the notebook stores, the cell's code folded under
it, and a link to the notebook's section (``--notebooks``: where the site's notebook pages are,
relative to the deck; default ``../notebooks/``, as the site places the deck). Press S for the
speaker notes (lecture.json's "note").

reveal.js is the one the ``sphinx-revealjs`` package (docs extra) ships, MathJax the site's
(``sphinx-mathjax-offline``); both are copied into OUT_FOLDER with the figures, so the folder
can be carried to a lecture room and opened from the disk. The site's build makes it as
``deck/`` beside its pages (docs/conf.py); tests/test_deck.py shows it in headless Chromium at
1920 x 1080 and checks that every slide fits the screen.
"""

from __future__ import annotations

import argparse
import base64
import hashlib
import html
import json
import re
import shutil
import sys
from collections.abc import Sequence
from importlib.util import find_spec
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
LECTURE = REPO / "notebooks" / "lecture.json"
NEEDS = 'pip install -e ".[docs]"'
# what the deck takes from each package: reveal.js's script, style sheets, the white theme and
# its font, the speaker notes; MathJax's TeX-to-HTML component and its fonts
REVEAL_FILES = [
    "dist/reveal.js",
    "dist/reset.css",
    "dist/reveal.css",
    "dist/theme/white.css",
    "dist/theme/fonts/source-sans-pro",
    "plugin/notes/notes.js",
    "LICENSE",
]
MATHJAX_FILES = ["tex-chtml.js", "output/chtml/fonts/woff-v2"]


class DeckError(Exception):
    """A slide the deck cannot make: its one-line message names the file and the field."""


def _package_folder(package: str, inside: str) -> Path:
    spec = find_spec(package)
    if spec is None or not spec.submodule_search_locations:
        raise DeckError(f"{package} is not installed ({NEEDS})")
    folder = Path(next(iter(spec.submodule_search_locations))) / inside
    if not folder.is_dir():
        raise DeckError(f"{package} has no {inside}/ (the docs extra pins the version that has)")
    return folder


def reveal_folder() -> Path:
    return _package_folder("sphinx_revealjs", "_static/revealjs")


def mathjax_folder() -> Path:
    return _package_folder("sphinx-mathjax-offline", "static/mathjax")


# ---- reading lecture.json and the notebooks ----------------------------------------------------


def load_lecture(path: Path = LECTURE) -> dict:
    """lecture.json, its shape checked: a one-line error names the field."""
    try:
        lecture = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError) as why:
        raise DeckError(f"{path}: {why}") from None
    slides = lecture.get("slides")
    if not isinstance(slides, list) or not slides:
        raise DeckError(f"{path}: slides: must be a non-empty list")
    for k, slide in enumerate(slides):
        for field, kind in (("title", str), ("notebook", str), ("cell", str), ("quotes", list)):
            if not isinstance(slide.get(field), kind):
                raise DeckError(f"{path}: slides[{k}].{field}: must be a {kind.__name__}")
        if slide.get("figure") is not None and not isinstance(slide["figure"], str):
            raise DeckError(f"{path}: slides[{k}].figure: must be a string or null")
    return lecture


def _cells(notebook: Path) -> list[dict]:
    return json.loads(notebook.read_text(encoding="utf-8"))["cells"]


def figure_cell(cells: list[dict], figure: str, where: str) -> dict:
    """The one code cell whose code holds ``figure``."""
    found = [c for c in cells if c["cell_type"] == "code" and figure in "".join(c["source"])]
    if len(found) != 1:
        raise DeckError(f"{where}: {len(found)} code cells hold {figure!r}, not one")
    return found[0]


def stored_figure(cell: dict, where: str) -> bytes:
    """The picture the cell stores (its last, where it shows several)."""
    pictures = [
        o["data"]["image/png"] for o in cell.get("outputs", []) if "image/png" in o.get("data", {})
    ]
    if not pictures:
        raise DeckError(f"{where}: its cell stores no picture (run python notebooks/execute.py)")
    return base64.b64decode(pictures[-1])


HEADING = re.compile(r"^(#{1,6})\s+(.*)$")


def section_anchor(cells: list[dict], heading: str, where: str) -> str:
    """The id the site gives the section that ``heading`` (a Markdown heading line of the
    notebook) opens: docutils' id of its text."""
    from docutils.nodes import make_id

    for cell in cells:
        if cell["cell_type"] != "markdown":
            continue
        for line in "".join(cell["source"]).splitlines():
            if line.strip() == heading.strip():
                match = HEADING.match(line.strip())
                if match:
                    return make_id(_plain(match.group(2)))
    raise DeckError(f"{where}: no Markdown heading {heading!r} in the notebook")


def _plain(text: str) -> str:
    """A heading's text as the page shows it: no Markdown marks, no $ around formulas."""
    return re.sub(r"[`*$]", "", text)


# ---- writing the deck ------------------------------------------------------------------------


BOLD = re.compile(r"\*\*(.+?)\*\*", re.S)
MATH = re.compile(r"(?<!\\)(\$\$.+?\$\$|\$.+?(?<!\\)\$)", re.S)
BARE_TEX = re.compile(r"\\[a-zA-Z]+(?:\{[^{}]*\})*")


def _bare_tex(text: str) -> str:
    """The slide's TeX outside $...$ (\\mathbf{u}, as the lecture's text writes some of its
    vectors) set between \\( \\) for MathJax to typeset: the same letters, as formulas."""
    parts = MATH.split(text)
    return "".join(
        part if k % 2 else BARE_TEX.sub(lambda m: f"\\({m.group(0)}\\)", part)
        for k, part in enumerate(parts)
    )


def _quote_html(quote: str) -> str:
    """A quote as the slide sets it, its words as they are: pseudo-code (lines that open and
    close braces) as a code block, tab-separated lines (a data sheet) as a table, a "- " item
    as a bullet, the text's **bold** as bold and its line breaks kept; $...$ is left for
    MathJax."""
    text = quote.strip("\n")
    lines = text.split("\n")
    if len(lines) > 1 and any(line.rstrip().endswith("{") for line in lines):
        return f'<pre class="pseudo-code"><code>{html.escape(text)}</code></pre>'
    if len(lines) > 1 and all("\t" in line for line in lines):
        rows = "".join(
            "<tr>" + "".join(f"<td>{html.escape(cell)}</td>" for cell in line.split("\t")) + "</tr>"
            for line in lines
        )
        return f'<table class="quote">{rows}</table>'
    words = BOLD.sub(r"<strong>\1</strong>", _bare_tex(html.escape(text))).replace("\n", "<br>")
    if text.startswith("- "):
        return f'<ul class="quote"><li>{words[2:]}</li></ul>'
    return f'<p class="quote">{words}</p>'


def _code_html(source: str) -> str:
    from pygments import highlight
    from pygments.formatters import HtmlFormatter
    from pygments.lexers import PythonLexer

    return highlight(source, PythonLexer(), HtmlFormatter(noclasses=True, nowrap=False))


def slide_html(slide: dict, picture: str | None, code: str | None, link: str) -> str:
    quotes = "".join(_quote_html(q) for q in slide["quotes"])
    parts = [f"<h2>{html.escape(slide['title'])}</h2>"]
    kind = "text" if quotes else "title-only"
    if picture:
        kind = "figure" if quotes else "picture"
        figure = (
            f'<figure><img src="figures/{picture}" alt="{html.escape(slide["title"])}">'
            f"<details><summary>the code that draws it</summary>{_code_html(code or '')}</details>"
            "</figure>"
        )
        words = f'<div class="words">{quotes}</div>' if quotes else ""
        parts.append(f'<div class="body">{words}{figure}</div>')
    elif quotes:
        parts.append(f'<div class="body"><div class="words">{quotes}</div></div>')
    section = _plain(HEADING.sub(r"\2", slide["cell"].strip()))
    parts.append(
        f'<p class="source"><a href="{html.escape(link)}">{html.escape(slide["notebook"])}: '
        f"{html.escape(section)}</a></p>"
    )
    if slide.get("note"):
        parts.append(f'<aside class="notes">{html.escape(slide["note"])}</aside>')
    # a slide of many words gives them more of its width (and, the most, a smaller type)
    weight = sum(len(q) for q in slide["quotes"]) + 40 * len(slide["quotes"])
    density = " dense" if weight > 1000 else " full" if weight > 600 else ""
    return f'<section class="{kind}{density}">{"".join(parts)}</section>'


STYLE = """
.reveal { font-size: 34px; }
.reveal .slides { text-align: left; }
.reveal .slides section { height: 100%; display: flex !important; flex-direction: column; }
.reveal h2 { font-size: 1.6em; margin: 0 0 0.4em; line-height: 1.3; text-transform: none; }
.reveal section.title-only h2 { font-size: 2.4em; margin: auto 0; text-align: center; }
.reveal .body { display: flex; gap: 1.2em; flex: 1 1 auto; min-height: 0; align-items: flex-start; }
.reveal .words { flex: 1 1 40%; min-width: 0; }
.reveal section.picture .body { justify-content: center; }
.reveal figure { flex: 1 1 60%; margin: 0; min-width: 0; max-height: 100%; display: flex;
  flex-direction: column; align-items: center; }
.reveal figure img { max-width: 100%; max-height: 820px; object-fit: contain; margin: 0; }
.reveal section.text .words { flex: 1 1 100%; }
.reveal section.full .words { flex-basis: 50%; }
.reveal section.dense .words { flex-basis: 62%; font-size: 0.9em; }
.reveal .words:has(pre.pseudo-code) { flex: 0 0 auto; }
.reveal p.quote { margin: 0 0 0.5em; line-height: 1.3; }
.reveal pre.pseudo-code { width: auto; margin: 0 0 0.5em; box-shadow: none; font-size: 0.8em; }
.reveal pre.pseudo-code code { max-height: none; padding: 0.4em 0.6em; background: #f4f4f4;
  line-height: 1.25; }
.reveal ul.quote { margin: 0 0 0.5em 1.2em; line-height: 1.3; }
.reveal table.quote { margin: 0 0 0.5em; font-size: 0.9em; }
.reveal table.quote td { padding: 0.1em 0.6em 0.1em 0; border: none; }
.reveal details { font-size: 0.7em; align-self: stretch; margin-top: 0.3em; }
.reveal details pre { margin: 0; max-height: 480px; overflow: auto; font-size: 0.75em; }
.reveal p.source { font-size: 0.55em; margin: 0.3em 0 0; flex: 0 0 auto; }
"""

PAGE = """<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<link rel="stylesheet" href="reveal/dist/reset.css">
<link rel="stylesheet" href="reveal/dist/reveal.css">
<link rel="stylesheet" href="reveal/dist/theme/white.css">
<style>{style}</style>
</head>
<body>
<div class="reveal"><div class="slides">
{slides}
</div></div>
<script src="reveal/dist/reveal.js"></script>
<script src="reveal/plugin/notes/notes.js"></script>
<script>
// formulas first (the slides' own TeX, $...$ and $$...$$), then reveal.js lays the slides out
window.MathJax = {{
  tex: {{ inlineMath: [["$", "$"], ["\\\\(", "\\\\)"]], processEscapes: true }},
  startup: {{
    pageReady: () => MathJax.startup.defaultPageReady().then(() => {{
      Reveal.initialize({{ width: 1920, height: 1080, margin: 0.02, hash: true,
                           transition: "none", center: false, plugins: [RevealNotes] }});
    }}),
  }},
}};
</script>
<script src="mathjax/tex-chtml.js"></script>
</body>
</html>
"""


def build(
    out: Path,
    lecture_path: Path = LECTURE,
    notebooks_url: str = "../notebooks/",
    notebooks: Path = REPO / "notebooks",
) -> int:
    """Write the deck into ``out`` (whole, or nothing where a slide cannot be made); returns the
    number of slides."""
    lecture = load_lecture(lecture_path)
    reveal, mathjax = reveal_folder(), mathjax_folder()
    sections, pictures = [], {}
    for k, slide in enumerate(lecture["slides"]):
        where = f"{lecture_path}: slides[{k}] ({slide['title']})"
        notebook = notebooks / slide["notebook"]
        if not notebook.is_file():
            raise DeckError(f"{where}.notebook: no such notebook {slide['notebook']}")
        cells = _cells(notebook)
        anchor = section_anchor(cells, slide["cell"], f"{where}.cell")
        link = f"{notebooks_url}{notebook.stem}.html#{anchor}"
        picture = code = None
        if slide.get("figure"):
            cell = figure_cell(cells, slide["figure"], f"{where}.figure")
            png = stored_figure(cell, f"{where}.figure")
            picture = hashlib.sha256(png).hexdigest()[:16] + ".png"
            pictures[picture] = png
            code = "".join(cell["source"])
        sections.append(slide_html(slide, picture, code, link))
    staging = out.with_name(f".{out.name}.part")
    shutil.rmtree(staging, ignore_errors=True)
    (staging / "figures").mkdir(parents=True)
    try:
        for name, png in pictures.items():
            (staging / "figures" / name).write_bytes(png)
        for inside in REVEAL_FILES:
            _copy(reveal / inside, staging / "reveal" / inside)
        for inside in MATHJAX_FILES:
            _copy(mathjax / inside, staging / "mathjax" / inside)
        page = PAGE.format(
            title=html.escape(lecture.get("lecture", "The lecture")),
            style=STYLE,
            slides="\n".join(sections),
        )
        (staging / "index.html").write_text(page, encoding="utf-8")
        shutil.rmtree(out, ignore_errors=True)
        staging.rename(out)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return len(sections)


def _copy(source: Path, target: Path) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    if source.is_dir():
        shutil.copytree(source, target)
    else:
        shutil.copyfile(source, target)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python docs/make_deck.py", description=__doc__.split("\n")[0]
    )
    parser.add_argument("-o", "--out", type=Path, default=REPO / "docs" / "_build" / "deck")
    parser.add_argument("--lecture", type=Path, default=LECTURE, help=argparse.SUPPRESS)
    parser.add_argument("--notebooks", default="../notebooks/", metavar="URL")
    args = parser.parse_args(argv)
    try:
        count = build(args.out, args.lecture, args.notebooks)
    except DeckError as why:
        print(f"docs/make_deck.py: error: {why}", file=sys.stderr)
        return 1
    print(f"{args.out / 'index.html'}: {count} slides")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Sphinx configuration of raykit's documentation site.

    pip install -e ".[docs]"
    sphinx-build -W --keep-going -b html docs docs/_build/html

The pages are Markdown (MyST), so they read the same on a repository host and on the site; the
lecture notebooks are shown from their stored outputs (myst-nb, never executed here: nbval in
the test suite is what runs them); the API reference is made from the docstrings.
"""

from __future__ import annotations

import hashlib
import json
import re
import runpy
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
REPO = DOCS.parent
sys.path.insert(0, str(REPO))  # raykit_grading and raykit from this clone, installed or not

project = "raykit"
author = "raykit developers"
copyright = "2026, raykit developers"

extensions = [
    "myst_nb",  # Markdown pages (it brings myst-parser) and the notebooks
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    # napoleon, not numpydoc: the docstrings are prose with Sphinx roles and a few reST headings
    # of their own ("Conventions ..."), rarely a "Parameters" section; napoleon turns the
    # sections it knows and leaves the rest as it is, where numpydoc expects every docstring
    # in its layout and warns (and so fails -W) on the others
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    # MathJax 3.2.2 served from the site itself (the sphinx-mathjax-offline package of the docs
    # extra copies it into _static/mathjax/ as the build ends), not from a CDN: the pages'
    # formulas must render in a lecture room or on a train with no network
    "sphinx-mathjax-offline",
]

# ---- sources -------------------------------------------------------------------------------
exclude_patterns = ["_build", "**.ipynb_checkpoints"]
# .rst first: autosummary writes its pages (api/generated/, git-ignored) with the first suffix
source_suffix = {".rst": "restructuredtext", ".md": "myst-nb", ".ipynb": "myst-nb"}


def _copy_notebooks() -> None:
    """The notebooks stay in notebooks/, where nbval and Jupyter find them; the site shows copies
    in docs/notebooks/ (git-ignored), rewritten only when a notebook changed, so that a second
    build reads none of them again."""
    copies = DOCS / "notebooks"
    copies.mkdir(exist_ok=True)
    for notebook in sorted((REPO / "notebooks").glob("*.ipynb")):
        copy = copies / notebook.name
        if not copy.exists() or copy.read_bytes() != notebook.read_bytes():
            copy.write_bytes(notebook.read_bytes())
    for copy in copies.glob("*.ipynb"):
        if not (REPO / "notebooks" / copy.name).exists():
            copy.unlink()


_copy_notebooks()
root_doc = "index"

# commands are shown as typed: no "--" turned into a dash, no quotes curled
smartquotes = False

# ---- MyST and the notebooks ----------------------------------------------------------------
myst_enable_extensions = ["colon_fence", "dollarmath", "deflist"]
myst_heading_anchors = 3  # "page.md#a-heading" links, as a repository host makes them
nb_execution_mode = "off"  # rendered from the outputs stored in the notebooks, no kernel, no pandoc
nb_merge_streams = True
# no widget manager: Jupyter's (require.js and @jupyter-widgets/html-manager) comes from a CDN,
# which a page with no network cannot reach, and an interact's slider redraws its figure in a
# Python kernel, which the site does not have; each slider cell shows instead plain HTML sliders
# over pictures its own function drew beforehand (_slider_cells below)
nb_ipywidgets_js: dict[str, dict[str, str]] = {}
# the site's own copy of MathJax (see extensions above), never a CDN's; tex-chtml reads the TeX
# that MyST's dollarmath and the notebooks' \( \) write
mathjax_path = "mathjax/tex-chtml.js"

# ---- API reference -------------------------------------------------------------------------
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
# "On this page" lists a class's methods under the class, as "progress()", not as
# "CompileClock.progress()": the column is narrow, and the nesting already names the class
toc_object_entries_show_parents = "hide"
autodoc_typehints = "description"
autodoc_typehints_format = "short"
# numba is the optional compiled engine's: without it, raykit.engine.compiled is documented from
# its source with numba mocked (njit and friends hand back the function they decorate);
# _grading is what raykit_grading is called inside the starter kit, where selfcheck.py runs
# as check.py
autodoc_mock_imports = ["numba", "_grading"]
napoleon_google_docstring = False
napoleon_numpy_docstring = True

# ---- links ---------------------------------------------------------------------------------
# The links inside the site are checked by the html build itself: MyST resolves every Markdown
# link (a page, a heading's anchor, a file, an image) and warns when it cannot, which -W turns
# into a failure. "-b linkcheck" would add only the web, which it must not fetch here (CI has
# no network, and another site's being up is not this repository's to test).
linkcheck_ignore = [r"https?://.*"]

# ---- look ----------------------------------------------------------------------------------
html_theme = "pydata_sphinx_theme"
html_title = "raykit"
html_logo = None
# _static/raykit.css: long names wrap instead of widening the page (tests/test_site.py)
html_static_path = ["_static"]
html_css_files = ["raykit.css"]
html_js_files = [("sliders.js", {"defer": "defer"})]
html_show_sourcelink = False
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 6,
    # a search button, not a search field: the field pushed the menu onto a second line
    "navbar_persistent": ["search-button"],
    "secondary_sidebar_items": ["page-toc"],
    "footer_start": ["copyright"],
    "footer_end": [],
}
html_sidebars = {"index": [], "students": [], "instructors": [], "lecturers": []}


def _top_section(env, docname: str, root: str) -> str:
    """The page of the site's top menu that ``docname`` is under (itself, for a top page)."""
    includes = env.toctree_includes
    parents = {child: parent for parent, children in includes.items() for child in children}
    while parents.get(docname, root) != root:
        docname = parents[docname]
    return docname


def _no_empty_sidebar(app, pagename: str, templatename, context: dict, doctree) -> None:
    """The left column ("Section Navigation") lists the pages under the current page's top menu
    entry; for a top page with none under it (the gallery, rendering, speed, every page under
    "More", the search and index pages) the theme still drew it, 320 pixels wide and empty, and
    the text beside it too narrow for its commands. Draw no column there."""
    top = _top_section(app.env, pagename, app.config.root_doc)
    if not app.env.toctree_includes.get(top):
        context["sidebars"] = []


# An API page's name is one long word of dotted parts (raykit.engine.compiled.billboards), which
# the browser, with no other place to break it, broke inside a part wherever it names a page or
# an object: in the footer's "previous" and "next" links, in the left column ("Section
# Navigation", "compiled.billbo|ards" at 1280 px) and the right one ("On this page"), in the
# page's headings ("raykit.engine.compiled.bil|lboards") and in each signature (a parameter
# "b|oard"). A break is offered after each dot instead, and in a signature after its opening
# parenthesis too, before its first parameter (the others break at the space after their
# comma); raykit.css lets them be taken, and tests/test_site.py checks that no word is broken.
#
# a tag, passed over whole so that no dot inside one (id="raykit.rays") is looked at; or a dot
# in the text between a name and the next name's first letter, tags allowed between them (a
# signature's "raykit.rays." and "dot" are two elements), but not a number's (1.5)
TAG_OR_DOT_IN_A_NAME = re.compile(r"<[^>]*>|(?<=\w)\.(?=(?:<[^>]*>)*[^\W\d])")


def _break_after_dots(html: str) -> str:
    """``html`` with a <wbr> after each dot of a dotted name in its text (not in its tags)."""
    return TAG_OR_DOT_IN_A_NAME.sub(lambda m: m[0] if m[0] != "." else ".<wbr>", html)


# a page's headings and the signatures of its API entries (autodoc's <dt class="sig ...">), in
# the page's body as Sphinx wrote it: neither nests in another of its kind
HEADING_OR_SIGNATURE = re.compile(r"<(h[1-6])\b.*?</\1>|<dt class=\"sig\b.*?</dt>", re.S)
OPENING_PARENTHESIS = '<span class="sig-paren">(</span>'


def _headings_and_signatures_break_at_dots(body: str) -> str:
    return HEADING_OR_SIGNATURE.sub(
        lambda found: _break_after_dots(found.group(0)).replace(
            OPENING_PARENTHESIS, OPENING_PARENTHESIS + "<wbr>"
        ),
        body,
    )


def _page_names_break_at_dots(app, pagename, templatename, context: dict, doctree) -> None:
    for key in ("prev", "next"):
        link = context.get(key)
        if link and link.get("title"):
            link["title"] = _break_after_dots(link["title"])
    # the theme's functions that draw the left column and the right one, set by the theme for
    # each page (the right one's, asked for the HTML it shows, not the tree it reads)
    draw_column = context.get("generate_toctree_html")
    if draw_column is not None:
        context["generate_toctree_html"] = lambda *args, **kwargs: _break_after_dots(
            str(draw_column(*args, **kwargs))
        )
    draw_contents = context.get("generate_toc_html")
    if draw_contents is not None:
        context["generate_toc_html"] = lambda kind="html": (
            _break_after_dots(str(draw_contents(kind))) if kind == "html" else draw_contents(kind)
        )
    if context.get("body"):
        context["body"] = _headings_and_signatures_break_at_dots(context["body"])


# ---- pages written for a repository host, read by Sphinx -------------------------------------
BENCHMARK_TITLE = re.compile(r"\A\s*#\s")


PLOT_ARGUMENT = re.compile(r"--plot docs/benchmarks/([\w.-]+\.png)")


def _benchmark_page(docname: str, text: str) -> str:
    """A benchmark page is what a benchmark command printed. Some start with the command, not a
    title: give those a title from their file name, so that the page has one in the site's
    menus. Some name their plot (``--plot docs/benchmarks/X.png``, or X.png beside the page
    with the page's name) without showing it: show it at the end."""
    if not docname.startswith("benchmarks/"):
        return text
    stem = docname.removeprefix("benchmarks/")
    if not BENCHMARK_TITLE.match(text):
        text = f"# Benchmark: {stem.replace('_', ' ')}\n\n{text}"
    plots = dict.fromkeys([*PLOT_ARGUMENT.findall(text), f"{stem}.png"])
    for plot in plots:
        if (DOCS / "benchmarks" / plot).exists() and f"]({plot})" not in text:
            text += f"\n\n![the plot of this run: {plot}]({plot})\n"
    return text


def _notebook_links(docname: str, text: str) -> str:
    """The notebooks link to pages and pictures as ``../docs/PAGE`` (from notebooks/ in the
    repository); on the site they are in docs/notebooks/, where the same file is ``../PAGE``."""
    if not docname.startswith("notebooks/"):
        return text
    return text.replace("](../docs/", "](../")


# ---- the notebooks' sliders ------------------------------------------------------------------
# docs/make_slider_frames.py drew, for each slider cell (a cell whose stored output is a widget),
# its function's figure at every stop of every slider, into _static/sliders/NOTEBOOK/K/ with a
# sliders.json; on the site the widget's output becomes a plain HTML slider a control over
# those pictures (_static/sliders.js moves them).
SLIDERS = DOCS / "_static" / "sliders"
WIDGET = "application/vnd.jupyter.widget-view+json"


def _slider_html(manifest: dict, notebook: str, number: int) -> str:
    from html import escape

    folder = f"../_static/sliders/{Path(notebook).stem}/{number}/"
    rows = []
    for k, control in enumerate(manifest["controls"]):
        name, labels, first = control["name"], control["labels"], control["first"]
        ident = f"slider-{Path(notebook).stem}-{number}-{k}"
        if all(label.lstrip("-").replace(".", "", 1).isdigit() for label in labels):
            field = (
                f'<input type="range" id="{ident}" data-control="{k}" min="0" '
                f'max="{len(labels) - 1}" step="1" value="{first}">'
                f'<output data-for="{ident}">{escape(labels[first])}</output>'
            )
        else:
            options = "".join(
                f'<option value="{i}"{" selected" if i == first else ""}>{escape(label)}</option>'
                for i, label in enumerate(labels)
            )
            field = f'<select id="{ident}" data-control="{k}">{options}</select>'
        rows.append(f'<label for="{ident}">{escape(name)}</label>{field}')
    # inside <script>, "</" would end it early
    data = json.dumps({"folder": folder, "controls": manifest["controls"]}).replace("</", "<\\/")
    return (
        '<div class="raykit-sliders">'
        f'<div class="raykit-sliders-controls">{"".join(rows)}</div>'
        f'<img src="{folder}{manifest["first"]}" alt="{escape(manifest["function"])}() at the '
        "sliders' setting\">"
        '<p class="raykit-sliders-note">One slider at a time, the others at their first setting: '
        f"each picture was drawn by this cell's {escape(manifest['function'])}() before the site "
        "was built (docs/make_slider_frames.py). In Jupyter the sliders combine freely.</p>"
        '<script type="application/json" class="raykit-sliders-data">'
        f"{data}</script></div>"
    )


def _slider_cells(app, docname: str, text: str) -> str:
    """A notebook's slider cells, their widget output replaced by HTML sliders over the pictures
    docs/make_slider_frames.py drew. A slider cell with no pictures, or whose code changed since
    they were drawn, is a warning (an error with -W): run that command."""
    if not docname.startswith("notebooks/") or WIDGET not in text:
        return text
    from sphinx.util import logging

    notebook = json.loads(text)
    name = Path(docname).name + ".ipynb"
    number = 0
    for cell in notebook["cells"]:
        outputs = cell.get("outputs", [])
        if not any(WIDGET in o.get("data", {}) for o in outputs):
            continue
        number += 1
        found = SLIDERS / Path(docname).name / str(number) / "sliders.json"
        manifest = json.loads(found.read_text()) if found.exists() else None
        code = hashlib.sha256("".join(cell["source"]).encode("utf-8")).hexdigest()
        if manifest is None or manifest["code"] != code:
            logging.getLogger(__name__).warning(
                "notebooks/%s: slider cell %d: %s: run python docs/make_slider_frames.py",
                name,
                number,
                "no pictures" if manifest is None else "its code changed since its pictures",
                location=docname,
            )
            continue
        html = _slider_html(manifest, name, number)
        cell["outputs"] = [
            {"output_type": "display_data", "metadata": {}, "data": {"text/html": html}}
            if WIDGET in o.get("data", {})
            else o
            for o in outputs
        ]
    return json.dumps(notebook)


def _source_read(app, docname: str, source: list[str]) -> None:
    text = _notebook_links(docname, _benchmark_page(docname, source[0]))
    source[0] = _slider_cells(app, docname, text)


# ---- docstrings written for help() and a terminal, read as reStructuredText ------------------
LIST_ITEM = re.compile(r"^\s*([*-]|\d+\.|\(\w\))\s")
UNDERLINE = re.compile(r"^([-=~^])\1{2,}$")


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


def _escape_bars(line: str) -> str:
    """|v| is a length in the docstrings, not a reST substitution: escape the bars outside
    ``literals``."""
    parts = line.split("``")
    return "``".join(p if k % 2 else p.replace("|", "\\|") for k, p in enumerate(parts))


def docstring_as_written(lines: list[str]) -> list[str]:
    """The docstrings set formulas and diagrams apart by indenting them after a blank line (as
    in the slides), write |v| for a length, and underline a heading to the width of its source
    text; reST would read those as a block quote (and trip over a diagram's own indents), a
    substitution, and a short underline. Show such a block as written (a literal block), the bars
    as bars, and the heading as a heading."""
    out: list[str] = []
    literal_indent: int | None = None  # inside a literal block: the indent of its paragraph
    for line in lines:
        blank = not line.strip()
        if literal_indent is not None:
            if blank or _indent(line) > literal_indent:
                out.append(line)
                continue
            literal_indent = None
        previous = out[-1] if out else ""
        paragraph_end = next((j for j in range(len(out) - 1, -1, -1) if out[j].strip()), None)
        after_blank = bool(out) and not out[-1].strip() and paragraph_end is not None
        if not blank and after_blank and not LIST_ITEM.match(line):
            last = out[paragraph_end]
            start = paragraph_end
            while start > 0 and out[start - 1].strip():
                start -= 1
            first = out[start]
            item = LIST_ITEM.match(first)
            content = item.end() if item and start == paragraph_end else _indent(last)
            if (
                _indent(line) > content
                and not first.lstrip().startswith("..")
                and not UNDERLINE.match(last.strip())
            ):
                if not last.rstrip().endswith("::"):
                    out[paragraph_end] = last.rstrip() + " ::"
                literal_indent = content
                out.append(line)
                continue
        underline = UNDERLINE.match(line.strip()) and _indent(line) == _indent(previous)
        if underline and previous.strip():
            line = line.strip()[0] * max(len(line.strip()), len(previous.strip()))
            line = " " * _indent(previous) + line
        out.append(line if blank else _escape_bars(line))
    return out


# each reference function's compiled twin, from the twin table (raykit/engine/compiled/twins.py,
# read as a file: importing it through its package would import numba). Added here, in the
# build, so that the sources, and the student release made from them, never hold the line
TWINS = REPO / "raykit/engine/compiled/twins.py"
twin_lines = runpy.run_path(str(TWINS))["doc_lines"] if TWINS.exists() else lambda name: []


def _process_docstring(app, what, name, obj, options, lines: list[str]) -> None:
    lines[:] = docstring_as_written(lines)
    if what in ("function", "method"):
        lines += [line for twin in twin_lines(name) for line in ("", twin)]


# ---- tables ---------------------------------------------------------------------------------
# A table too wide for the page scrolls sideways in its own block (the theme's); the browser
# would rather squeeze it into the page's width, breaking every cell wherever it can: a
# benchmark's "5.9 ms" or "rays per pixel" set one word a line. A cell of a few words keeps them
# on one line (raykit.css: td.few-words; on a phone, only a very short one: td.short), and a
# longer one wraps, in a column no narrower than a few words (tests/test_site.py measures both).
FEW_WORDS = 24  # characters
SHORT = 16


def _mark_few_word_cells(app, doctree, docname: str) -> None:
    from docutils import nodes

    for entry in doctree.findall(nodes.entry):
        text = " ".join(entry.astext().split())
        if len(text) <= FEW_WORDS:
            entry["classes"].append("few-words")
        if len(text) <= SHORT:
            entry["classes"].append("short")


def _autosummary_table_as_written(translator, node) -> None:
    """autosummary writes its tables' signatures with no-break spaces, to keep each on one line;
    raykit.css keeps them on one line where there is room for it, and on a phone, where the
    summary goes under the name, lets a long one wrap at its spaces instead of inside a name."""


# ---- the lecture's slide deck -------------------------------------------------------------------
def _deck(app, exception) -> None:
    """The deck (docs/make_deck.py) as deck/ beside the site's pages, linked from the lecturer
    guide; its slides link to the notebooks' pages at ../notebooks/."""
    if exception is not None or app.builder.format != "html":
        return
    from sphinx.util import logging

    maker = runpy.run_path(str(DOCS / "make_deck.py"))
    try:
        maker["build"](Path(app.outdir) / "deck")
    except maker["DeckError"] as why:
        logging.getLogger(__name__).warning("the lecture's deck: %s", why)


def setup(app):
    from sphinx.ext.autosummary import autosummary_noop, autosummary_table

    app.connect("source-read", _source_read)
    app.connect("html-page-context", _no_empty_sidebar)
    # after the theme has set its functions for the page (it connects at the default, 500)
    app.connect("html-page-context", _page_names_break_at_dots, priority=900)
    app.connect("doctree-resolved", _mark_few_word_cells)
    app.connect("build-finished", _deck)
    app.add_node(
        autosummary_table, html=(_autosummary_table_as_written, autosummary_noop), override=True
    )
    app.connect("autodoc-process-docstring", _process_docstring)

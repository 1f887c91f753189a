"""The kit quotes the lecture word for word, and only where it says it does.

``notebooks/lecture.json`` lists every slide of the lecture in its order: its title, the words
the kit quotes from it (``quotes``), the lecture map's item that teaches it, the notebook cell
where it is taught and its figure: the code cell that draws it (``figure``, words of that cell),
or the stored picture that a Markdown cell of the item's section shows (``image``, its path from
notebooks/). Its quotations are the only text the kit presents as the slides': these tests check
that each is in its notebook's Markdown, that each (and each title) is on its slide in the
lecture's own text, that the quotations together hold every word of that text, and that
whatever the notebooks and the pages that quote the slides present as the slides' is one of
them; and that each figure is drawn, or shown, inside its item's section.

Presented as the slides' means: a span in quotation marks (“…” or "…") in prose; a block quote
(``> ``), whose paragraphs and list items are the slide's lines (a paragraph that is only a
bold slide title names the slide); a fenced block in a notebook's Markdown, or one marked
``text`` on a page (the slide's pseudo-code, line by line as the slide sets it); the first
column of a table headed "the slide's line"; and a sentence that says the slide says, writes,
calls or asks something, or gives the slide's words, which must hold a quotation or lead into
one. Whitespace is folded everywhere (the lecture text's line breaks and trailing spaces are
its extraction's, not the slide's); nothing else is.

The lecture's text is read from ``../shared/lecture/`` beside the repository (CI has it); where
it is absent, the checks against it skip, saying so.
"""

import functools
import json
import re
from pathlib import Path

import pytest

from conftest import REPO

DATA = json.loads((REPO / "notebooks" / "lecture.json").read_text())
SLIDES = DATA["slides"]
NOTEBOOKS = sorted((REPO / "notebooks").glob("*.ipynb"))
PAGES = ["README.md", "docs/index.md", "docs/lecture-map.md", "docs/lecturers.md"]
PAGES += ["docs/rendering.md", "docs/gallery.md"]  # pages that quote the slides
LECTURE = REPO.parent / "shared" / "lecture"
TEXT_FILE = LECTURE / Path(DATA["source"]).name


def fold(text: str) -> str:
    return " ".join(text.split())


@functools.cache
def _cells(path: Path) -> list[dict]:
    return json.loads(path.read_text())["cells"]


def _markdown(path: Path) -> str:
    return "\n\n".join(
        "".join(cell["source"]) for cell in _cells(path) if cell["cell_type"] == "markdown"
    )


def _slide_id(k: int) -> str:
    return f"{k + 1:02d} {SLIDES[k]['title']}"


def _id(slide: dict) -> str:
    return _slide_id(next(k for k, other in enumerate(SLIDES) if other is slide))


QUOTES = [fold(q) for slide in SLIDES for q in slide["quotes"]]
TITLES = {fold(slide["title"]) for slide in SLIDES}


# ---- the data ----------------------------------------------------------------------------


def test_every_slide_has_a_title_quotes_and_a_place_or_a_note_saying_why_not():
    assert DATA["lecture"] and DATA["source"]
    keys = {"title", "item", "notebook", "cell", "quotes", "figure"}
    for k, slide in enumerate(SLIDES):
        assert keys <= set(slide) <= keys | {"image", "note"}, _slide_id(k)
        assert isinstance(slide["title"], str) and slide["title"], _slide_id(k)
        assert isinstance(slide["quotes"], list), _slide_id(k)
        assert all(isinstance(q, str) and q.strip() for q in slide["quotes"]), _slide_id(k)
        assert slide["item"] is None or isinstance(slide["item"], int), _slide_id(k)
        assert slide["figure"] is None or isinstance(slide["figure"], str), _slide_id(k)
        image = slide.get("image")
        assert image is None or isinstance(image, str) and image, _slide_id(k)
        assert not (image and slide["figure"]), f"{_slide_id(k)}: figure drawn or stored, not both"
        if slide["notebook"] is None or slide["cell"] is None:
            assert slide.get("note"), f"{_slide_id(k)}: taught nowhere, and no note says why"
        else:
            assert (REPO / "notebooks" / slide["notebook"]).is_file(), _slide_id(k)


@pytest.mark.parametrize("slide", SLIDES, ids=_id)
def test_each_quotation_is_in_its_notebooks_markdown(slide):
    if slide["notebook"] is None:
        assert not slide["quotes"], "a slide quoted nowhere has no quotations"
        return
    markdown = _markdown(REPO / "notebooks" / slide["notebook"])
    markdown = fold(re.sub(r"^[ \t]*>[ \t]?", "", markdown, flags=re.M))  # block quotes' marks
    missing = [q for q in slide["quotes"] if fold(q) not in markdown]
    assert not missing, f"notebooks/{slide['notebook']} does not quote {missing}"


@pytest.mark.parametrize("slide", [s for s in SLIDES if s["cell"]], ids=_id)
def test_each_slides_cell_starts_one_markdown_cell(slide):
    cells = _cells(REPO / "notebooks" / slide["notebook"])
    starts = [
        k
        for k, cell in enumerate(cells)
        if cell["cell_type"] == "markdown" and "".join(cell["source"]).startswith(slide["cell"])
    ]
    assert len(starts) == 1, f"{slide['notebook']}: {len(starts)} cells start {slide['cell']!r}"


@functools.cache
def _map_items() -> dict[int, tuple[str, str, str | None]]:
    """Map item -> (notebook, its cell's words, the next item's cell words in that notebook)."""
    rows = []
    for line in (REPO / "docs" / "lecture-map.md").read_text().splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split(" | ")]
        if len(cells) == 6 and cells[0].isdigit():
            path, words = re.fullmatch(r"`notebooks/([^`]+)`, at `([^`]+)`", cells[2]).groups()
            rows.append((int(cells[0]), path, words))
    return {
        item: (path, words, nxt[2] if nxt and nxt[1] == path else None)
        for (item, path, words), nxt in zip(rows, [*rows[1:], None], strict=True)
    }


def _section(item: int) -> tuple[int, int]:
    """(first cell, cell after the last) of map item ``item``'s section of its notebook."""
    path, start, end = _map_items()[item]
    sources = ["".join(c["source"]) for c in _cells(REPO / "notebooks" / path)]
    first = next(i for i, s in enumerate(sources) if start in s)
    last = next((i for i, s in enumerate(sources) if end in s), None) if end else None
    return first, last or len(sources)


def test_each_slide_is_taught_in_its_map_items_section():
    items = _map_items()
    assert {s["item"] for s in SLIDES} - {None} == set(items), "every map item has its slides"
    for k, slide in enumerate(SLIDES):
        if slide["item"] is None:
            continue
        path = items[slide["item"]][0]
        assert slide["notebook"] == path, f"{_slide_id(k)}: item {slide['item']} is in {path}"
        sources = ["".join(c["source"]) for c in _cells(REPO / "notebooks" / path)]
        here = next(i for i, s in enumerate(sources) if s.startswith(slide["cell"]))
        first, end = _section(slide["item"])
        assert first <= here < end, (
            f"{_slide_id(k)}: its cell is outside item {slide['item']}'s section of {path}"
        )


@pytest.mark.parametrize("slide", [s for s in SLIDES if s["figure"]], ids=_id)
def test_each_figure_is_drawn_by_one_code_cell_of_its_items_section(slide):
    cells = _cells(REPO / "notebooks" / slide["notebook"])
    code = [
        k
        for k, c in enumerate(cells)
        if c["cell_type"] == "code" and slide["figure"] in "".join(c["source"])
    ]
    assert len(code) == 1, f"{slide['notebook']}: {len(code)} code cells hold {slide['figure']!r}"
    outputs = cells[code[0]]["outputs"]
    assert any("image/png" in out.get("data", {}) for out in outputs), slide["figure"]
    if slide["item"] is not None:
        first, end = _section(slide["item"])
        assert first <= code[0] < end, f"cell {code[0]} is outside item {slide['item']}'s section"


@pytest.mark.parametrize("slide", [s for s in SLIDES if s.get("image")], ids=_id)
def test_each_stored_image_is_shown_by_one_markdown_cell_of_its_items_section(slide):
    path = REPO / "notebooks" / slide["notebook"]
    assert (path.parent / slide["image"]).is_file(), f"no such picture: {slide['image']}"
    shown = re.compile(r"!\[[^\]]*\]\(" + re.escape(slide["image"]) + r"\)")
    cells = _cells(path)
    showing = [
        k
        for k, c in enumerate(cells)
        if c["cell_type"] == "markdown" and shown.search("".join(c["source"]))
    ]
    assert len(showing) == 1, f"{slide['notebook']}: {len(showing)} cells show {slide['image']}"
    first, end = _section(slide["item"])
    assert first <= showing[0] < end, f"cell {showing[0]} is outside item {slide['item']}'s section"


# ---- the lecture's text ------------------------------------------------------------------


@pytest.fixture(scope="module")
def lecture() -> str:
    if not TEXT_FILE.is_file():
        pytest.skip(f"the lecture's text is not here ({TEXT_FILE}): CI checks it")
    return fold(TEXT_FILE.read_text())


def _slide_spans(text: str) -> list[tuple[int, int]]:
    """Where each slide's text runs in the folded lecture: from its title to the next title."""
    starts, at = [], 0
    for k, slide in enumerate(SLIDES):
        found = text.find(fold(slide["title"]), at)
        assert found >= 0, f"{_slide_id(k)}: no such title after the previous slide's"
        starts.append(found)
        at = found + len(fold(slide["title"]))
    return list(zip(starts, [*starts[1:], len(text)], strict=True))


def test_titles_are_the_lectures_in_its_order(lecture):
    _slide_spans(lecture)


def test_each_quotation_is_on_its_slide_in_the_lecture(lecture):
    wrong = []
    for k, (start, end) in enumerate(_slide_spans(lecture)):
        wrong += [
            (_slide_id(k), q) for q in SLIDES[k]["quotes"] if fold(q) not in lecture[start:end]
        ]
    assert not wrong, f"not on the slide, word for word: {wrong}"


def test_the_quotations_hold_every_word_of_the_lecture(lecture):
    # each slide's title and quotations, laid over its text, leave only list dashes and
    # the fences of its pseudo-code uncovered: no slide's words are left out
    left = []
    for k, (start, end) in enumerate(_slide_spans(lecture)):
        text = lecture[start:end]
        covered = [False] * len(text)
        for words in [SLIDES[k]["title"], *SLIDES[k]["quotes"]]:
            for hit in re.finditer(re.escape(fold(words)), text):
                covered[hit.start() : hit.end()] = [True] * len(hit.group())
        rest = "".join(c if not seen else " " for c, seen in zip(text, covered, strict=True))
        rest = rest.replace("```", " ").replace("-", " ").split()
        if rest:
            left.append((_slide_id(k), " ".join(rest)))
    assert not left, f"the lecture's words no quotation holds: {left}"


# ---- what the notebooks and pages present as the slides' --------------------------------

FENCE = re.compile(r"^[ \t]*(`{3,}|~{3,})[ \t]*([^\n`]*)\n(.*?)^[ \t]*\1[ \t]*$", re.M | re.S)
CODE_SPAN = re.compile(r"(`+)(?!`).*?(?<!`)\1(?!`)", re.S)
QUOTATION = re.compile(r"“([^”]*)”|\"([^\"]*)\"")
ATTRIBUTION = re.compile(
    r"\bthe slides?'?s? (?:own )?(?:words|sentence|text|answer|question|advice|definitions?|"
    r"reasons|term|caption|label)\b|\bthe slides? (?:says?|writes?|sets?|calls?|asks?|names?|"
    r"puts?)\b",
    re.I,
)
FENCED = "\x01fenced block\x01"
LIST_ITEM = re.compile(r"^\s*(?:[-*+]|\d+\.)\s+")


def _is_quotation(words: str) -> bool:
    """``words`` (folded) is a whole-word piece of a quotation of the data, or a title."""
    if not words or words in TITLES:
        return True
    for quote in QUOTES:
        for hit in re.finditer(re.escape(words), quote):
            before = quote[hit.start() - 1] if hit.start() else " "
            after = quote[hit.end()] if hit.end() < len(quote) else " "
            if not (words[0].isalnum() and before.isalnum()) and not (
                words[-1].isalnum() and after.isalnum()
            ):
                return True
    return False


def _is_pseudo_code(block: str) -> bool:
    """``block`` is one of the data's quotations whole, its lines as the slide sets them."""
    lines = [fold(line) for line in block.splitlines() if line.strip()]
    return any(
        lines == [fold(line) for line in q.splitlines() if line.strip()]
        for slide in SLIDES
        for q in slide["quotes"]
    )


def _presented(markdown: str, every_fence: bool) -> list[str]:
    """The strings ``markdown`` presents as the slides' that are not the slides'."""
    wrong = []
    fences = []

    def keep_fence(match: re.Match) -> str:
        info, body = match.group(2).strip(), match.group(3)
        if every_fence or info == "text":
            fences.append(body)
        return f"\n\n{FENCED}\n\n"  # a block of its own, whose words are not prose

    prose = FENCE.sub(keep_fence, markdown)
    wrong += [body for body in fences if not _is_pseudo_code(body)]
    # HTML tags are no text, but an autolink <https://...> is the slide's
    prose = re.sub(r"<[A-Za-z/!][^>\n]*>", lambda m: m[0] if "://" in m[0] else " ", prose)
    # code spans are no quotation marks' business, but a quotation may hold one
    spans: list[str] = []

    def mask(match: re.Match) -> str:
        spans.append(match.group())
        return f"\0{len(spans) - 1}\0"

    def unmask(text: str) -> str:
        return re.sub(r"\0(\d+)\0", lambda m: spans[int(m.group(1))], text)

    masked = CODE_SPAN.sub(mask, prose)
    blocks = [b for b in re.split(r"\n[ \t]*\n", masked) if b.strip()]
    for k, block in enumerate(blocks):
        lines = block.splitlines()
        if lines and all(line.lstrip().startswith(">") for line in lines):  # a block quote
            units, unit = [], []
            for line in lines:
                line = re.sub(r"^\s*>\s?", "", line)
                if not line.strip() or LIST_ITEM.match(line):
                    units.append(unit)
                    unit = []
                unit.append(LIST_ITEM.sub("", line))
            for words in (fold(unmask(" ".join(u))) for u in [*units, unit]):
                bold_title = re.fullmatch(r"\*\*(.+)\*\*", words)
                if not (bold_title and bold_title.group(1) in TITLES) and not _is_quotation(words):
                    wrong.append(words)
            continue
        if lines and lines[0].lstrip().startswith("|") and "the slide's line" in lines[0]:
            for row in lines[2:]:
                first = row.strip().strip("|").split("|")[0]
                words = fold(unmask(first).replace("`", "").replace("&nbsp;", " "))
                if not _is_quotation(words):
                    wrong.append(words)
            continue
        for match in QUOTATION.finditer(block):
            words = fold(unmask(match.group(1) if match.group(1) is not None else match.group(2)))
            if not _is_quotation(words):
                wrong.append(words)
        following = blocks[k + 1].lstrip() if k + 1 < len(blocks) else ""
        leads_in = block.rstrip().endswith(":") and following.startswith((">", FENCED, "|"))
        if ATTRIBUTION.search(block) and not QUOTATION.search(block) and not leads_in:
            wrong.append(f"{fold(unmask(block))} (says the slide says it, quoting nothing)")
    return wrong


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_what_a_notebook_presents_as_the_slides_is_the_slides(path):
    wrong = []
    for k, cell in enumerate(_cells(path)):
        if cell["cell_type"] == "markdown":
            source = "".join(cell["source"])
            heading = source.splitlines()[0] if source else ""
            wrong += [f"cell {k} ({heading}): {w!r}" for w in _presented(source, every_fence=True)]
    assert not wrong, f"notebooks/{path.name} presents as the slides' what is not: {wrong}"


@pytest.mark.parametrize("page", PAGES)
def test_what_a_page_presents_as_the_slides_is_the_slides(page):
    text = (REPO / page).read_text()
    wrong = _presented(text, every_fence=False)
    assert not wrong, f"{page} presents as the slides' what is not: {wrong}"

"""Progress bars for long work, on stderr, only for a person watching a terminal.

A bar is shown only when stderr is a terminal (never in a log, a pipe or a test's captured
output), and only once the work has run for ``DELAY`` seconds (tqdm's ``delay``), so a quick
command prints nothing extra. The bar is erased when the work ends (``leave=False``): what the
command prints afterwards is what it always printed. While a bar is shown, warnings are written
above it with ``tqdm.write`` instead of into the middle of its line.

tqdm is a core dependency: pure Python, with no dependencies of its own, and imported only
when a bar is about to be shown.
"""

from __future__ import annotations

import sys
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TextIO

DELAY = 1.0  # seconds of work before a bar appears


def wanted(stream: TextIO | None = None) -> bool:
    """Whether a bar would be seen: ``stream`` (default stderr) is an open terminal."""
    stream = sys.stderr if stream is None else stream
    try:
        return stream is not None and stream.isatty()
    except (AttributeError, ValueError):  # no isatty, or closed
        return False


@contextmanager
def progress_bar(
    total: int,
    description: str,
    unit: str = "it",
    *,
    stream: TextIO | None = None,
    delay: float = DELAY,
    force: bool = False,
) -> Iterator[Callable[[int], object] | None]:
    """``with progress_bar(total, "render") as advance:`` gives ``advance(n)`` to call as work
    is done, or None when no bar is shown (``stream``, default stderr, is not a terminal and
    ``force`` is false). Warnings raised inside go through ``tqdm.write``."""
    stream = sys.stderr if stream is None else stream
    if not (force or wanted(stream)):
        yield None
        return
    from tqdm import tqdm

    with tqdm(
        total=total,
        desc=description,
        unit=unit,
        unit_scale=total >= 10_000,  # 154k px, but 3/20 cells
        file=stream,
        leave=False,
        delay=delay,
        dynamic_ncols=True,
    ) as bar:
        shown = warnings.showwarning

        def above_the_bar(message, category, filename, lineno, file=None, line=None):
            text = warnings.formatwarning(message, category, filename, lineno, line)
            tqdm.write(text.rstrip("\n"), file=stream)

        warnings.showwarning = above_the_bar
        try:
            yield bar.update
        finally:
            warnings.showwarning = shown

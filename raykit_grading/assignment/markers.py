"""Solution markers, in the style of nbgrader and otter-grader.

In the solution (``raykit/``) a function body that students write looks like::

    def hit_plane(origins, directions, a, n):
        \"\"\"docstring, kept\"\"\"
        # BEGIN SOLUTION
        # hint: t = ((a - o)·n) / (d·n); rays parallel to the plane and hits with
        #       t <= 0 are MISS
        ...the solution...
        # END SOLUTION

and the student release replaces the whole region with
``raise NotImplementedError("hit_plane: t = ((a - o)·n) / (d·n); ...")`` at the same indentation.
"""

from __future__ import annotations

import re

BEGIN = re.compile(r"^(?P<indent>\s*)# BEGIN SOLUTION\s*$")
END = re.compile(r"^\s*# END SOLUTION\s*$")
HINT = re.compile(r"^\s*# hint: (?P<text>.*)$")
HINT_MORE = re.compile(r"^\s*#\s{6,}(?P<text>\S.*)$")
DEF = re.compile(r"^\s*def (?P<name>\w+)\(")


class MarkerError(ValueError):
    """Unbalanced or nested solution markers."""


def strip_solutions(source: str, path: str = "<source>") -> tuple[str, list[str]]:
    """The source with every solution region replaced by a NotImplementedError stub.

    Returns (new source, names of the functions stubbed).
    """
    out: list[str] = []
    stubbed: list[str] = []
    lines = source.split("\n")
    i = 0
    function = "?"
    while i < len(lines):
        line = lines[i]
        if match := DEF.match(line):
            function = match["name"]
        begin = BEGIN.match(line)
        if END.match(line):
            raise MarkerError(f"{path}:{i + 1}: END SOLUTION without BEGIN SOLUTION")
        if not begin:
            out.append(line)
            i += 1
            continue
        hint_parts = []
        i += 1
        if i < len(lines) and (match := HINT.match(lines[i])):
            hint_parts.append(match["text"].strip())
            i += 1
            while i < len(lines) and (match := HINT_MORE.match(lines[i])):
                hint_parts.append(match["text"].strip())
                i += 1
        while i < len(lines) and not END.match(lines[i]):
            if BEGIN.match(lines[i]):
                raise MarkerError(f"{path}:{i + 1}: BEGIN SOLUTION inside another")
            i += 1
        if i == len(lines):
            raise MarkerError(f"{path}: BEGIN SOLUTION in {function} is never ended")
        hint = " ".join(hint_parts) or "see the lecture slides"
        message = f"{function}: write this function. Hint: {hint}"
        out.append(f"{begin['indent']}raise NotImplementedError({message!r})")
        stubbed.append(function)
        i += 1  # past END SOLUTION
    return "\n".join(out), stubbed

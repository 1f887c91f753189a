"""README.md stays a front door: short, its links real, the commands CI runs in their blocks, and
no measured figure (those live on the benchmark pages under docs/benchmarks/)."""

import re

from conftest import REPO

README = (REPO / "README.md").read_text()


def _block(name: str) -> list[str]:
    """The lines of README's ``<!-- name ... -->`` block that .ci/run runs (fences left out)."""
    inside = README.split(f"<!-- {name}", 1)[1].split(f"<!-- /{name} -->", 1)[0]
    lines = inside.splitlines()[1:]  # the rest of the marker's own line
    return [line for line in lines if line.strip() and not line.startswith("```")]


def test_readme_is_at_most_150_lines():
    assert len(README.splitlines()) <= 150


def test_quickstart_block_renders_then_runs_the_quick_tests():
    assert _block("quickstart") == [
        "pip install -e . && raykit render scenes/classic.json -o classic.png",
        'pip install -e ".[test]" && python -m pytest -m "not slow"',
    ]


def test_full_suite_block_runs_every_test():
    assert _block("full-suite") == ["python -m pytest"]


def test_fast_lane_block_tests_the_compiled_engine():
    assert _block("fast-lane") == [
        'pip install -e ".[fast]" && python -m pytest tests/compiled tests/test_cli.py'
    ]


def test_every_relative_link_and_picture_in_readme_exists():
    targets = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README)
    local = [t for t in targets if not re.match(r"[a-z]+:", t)]
    assert local, "README links to its guides"
    missing = [t for t in local if not (REPO / t).exists()]
    assert missing == []


def test_readme_links_each_readers_guide():
    for guide in ("docs/students.md", "docs/instructors.md", "docs/lecturers.md"):
        assert f"]({guide})" in README


def test_readme_quotes_no_measured_time():
    # a time measured on some machine belongs on the page its benchmark command writes
    times = re.findall(r"\b\d+(?:\.\d+)? ?(?:ms|s|seconds|minutes)\b", README)
    spelled = re.findall(r"\babout (?:one|two|three|four|five|ten) (?:seconds|minutes)\b", README)
    assert times + spelled == []

"""A grading run's options from its command line (raykit_grading.grading.options): the times a
test may take, each refused in one line naming the option when it is no time at all."""

from __future__ import annotations

import argparse

import pytest

from raykit_grading.grading.options import add_grading_arguments, grading_options


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="grade")
    add_grading_arguments(parser, total_seconds=600.0)
    return parser


def test_a_tests_wall_time_bounds_its_cpu_time_and_the_total_is_the_submissions():
    parser = _parser()
    options = grading_options(
        parser.parse_args(["--wall-seconds", "4.5", "--total-seconds", "90"]), parser
    )
    assert (options.limits.wall_seconds, options.limits.cpu_seconds) == (4.5, 5)
    assert options.total_seconds == 90.0
    assert grading_options(parser.parse_args([]), parser).total_seconds == 600.0


NOT_SECONDS = "must be between 0 and 86400, got"


@pytest.mark.parametrize(
    "arguments, says",
    [
        (["--wall-seconds", "0"], f"argument --wall-seconds: {NOT_SECONDS} 0"),
        (["--total-seconds", "1e6"], f"argument --total-seconds: {NOT_SECONDS} 1e+06"),
        (
            ["--wall-seconds", "soon"],
            "argument --wall-seconds: must be a number of seconds, got 'soon'",
        ),
        (["--only", "9.9"], "--only 9.9: no test has that number or name"),
    ],
    ids=["no-wall-time", "a-total-past-a-day", "wall-time-in-words", "no-such-test"],
)
def test_a_time_that_is_no_time_or_a_test_that_is_none_is_refused_in_one_line(
    arguments, says, capsys
):
    parser = _parser()
    with pytest.raises(SystemExit) as refused:
        grading_options(parser.parse_args(arguments), parser)
    assert refused.value.code == 2
    said = capsys.readouterr().err.strip().splitlines()
    assert said[-1] == f"grade: error: {says}" and said[0].startswith("usage: grade")

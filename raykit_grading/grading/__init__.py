"""Grading: one submission taken in and graded test by test into Gradescope's results.json; a
class of them into a CSV, a report and each student's feedback page.

It runs wherever the grader runs (an instructor's machine, Gradescope's container,
PrairieLearn's): :mod:`raykit_grading.platforms` wires it to each.
"""

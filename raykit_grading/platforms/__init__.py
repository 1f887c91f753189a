"""The platforms a course grades on: Gradescope's autograder zip (:mod:`~.gradescope`),
PrairieLearn's grader image and question (:mod:`~.prairielearn`), and both in real Docker
containers, as the platforms build and run them (:mod:`~.containers`).

Each calls :mod:`raykit_grading.grading`; nothing below imports a platform.
"""

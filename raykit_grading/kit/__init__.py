"""What ships to students: copied into the starter kit as it is, so it imports nothing else of
the grader (``tests/grading/test_roles.py`` reads every import).

The release (:mod:`raykit_grading.assignment.release`) copies :mod:`~.selfcheck` as the kit's
``check.py`` and every other module here into its ``tests/_grading/``, the name they import
each other by there. The grader uses the same modules: :mod:`~.tasks` runs inside the sandbox
too, and :mod:`~.compare` judges every graded result.
"""

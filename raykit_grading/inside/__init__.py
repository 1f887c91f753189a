"""What runs inside the sandbox: the child that runs one task of a submission.

The sandbox (:mod:`raykit_grading.sandbox`) copies :mod:`~.child` and the kit's
:mod:`~raykit_grading.kit.tasks` into each task's work folder and starts the child with
Python's ``-I -S``: it imports nothing of the grader (the grader is not in its world) and
loads the tasks by path.
"""

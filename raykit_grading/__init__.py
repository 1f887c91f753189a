"""raykit_grading: the instructor's autograder and the student starter kit for raykit.

One module per verb, in the order a term uses them:

* ``markers``, ``release``: the student release, built from the solution by replacing every
  ``# BEGIN SOLUTION`` … ``# END SOLUTION`` region with a hint.
* ``catalog``: the grading tests, per stage, with points and visibility.
* ``sandbox``, ``child``: running a submission's code in a child process with limits, so that
  it can only hand back arrays.
* ``compare``, ``mistakes``: fair image comparison, and the classic mistakes that feedback can
  name.
* ``grade``, ``batch``: one submission to a Gradescope results.json; a folder of them to a CSV.
* ``gradescope``: the autograder zip.

``python -m raykit_grading --help`` lists the commands. It needs a clone of the course
repository: the example scenes (``scenes/``) and the hidden ones (``grading-scenes/``) are not
in any wheel.
"""

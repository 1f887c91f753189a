"""grading: the instructor's autograder and the student starter kit for raykit.

One subpackage-free module per verb, in the order a term uses them:

* :mod:`grading.markers`, :mod:`grading.release`: the student release, built from the solution
  by replacing every ``# BEGIN SOLUTION`` … ``# END SOLUTION`` region with a hint.
* :mod:`grading.catalog`: the grading tests, per stage, with points and visibility.
* :mod:`grading.sandbox`, :mod:`grading.child`: running a submission's code in a child process
  with limits, so that it can only hand back arrays.
* :mod:`grading.compare`, :mod:`grading.mistakes`: fair image comparison, and the classic
  mistakes that feedback can name.
* :mod:`grading.grade`, :mod:`grading.batch`: one submission to a Gradescope results.json; a
  folder of them to a CSV.
* :mod:`grading.gradescope`: the autograder zip.

``python -m grading --help`` lists the commands.
"""

"""raykit_grading: the instructor's autograder and the student starter kit for raykit.

``python -m raykit_grading --help`` lists the commands (:mod:`raykit_grading.__main__`). The
modules, in the order a term uses them:

The starter kit
    * :mod:`~raykit_grading.markers`: the ``# BEGIN SOLUTION`` … ``# END SOLUTION`` regions.
    * :mod:`~raykit_grading.release`: the student release, the solution with those regions
      replaced by hints, and its practice tests.
    * :mod:`~raykit_grading.cases`: one practice test on disk.
    * :mod:`~raykit_grading.selfcheck`: the release's ``check.py``.

The tests
    * :mod:`~raykit_grading.catalog`: the grading tests, per stage, with points and visibility.
    * :mod:`~raykit_grading.seeds`: the assignment's secret seed, from which inputs are drawn.
    * :mod:`~raykit_grading.mistakes`: the classic mistakes, made by the reference on purpose.
    * :mod:`~raykit_grading.compare`: arrays within a tolerance, images fairly at silhouettes,
      and the feedback shown for a failure.

Running a submission
    * :mod:`~raykit_grading.submissions`: taking a submission in, as plain files.
    * :mod:`~raykit_grading.workspace`: the grader's own private temporary folder.
    * :mod:`~raykit_grading.sandbox`: one task in a child process, its results taken back as
      untrusted; which kind of sandbox is used.
    * :mod:`~raykit_grading.isolation`: the bubblewrap sandbox, and the seccomp filter.
    * :mod:`~raykit_grading.confine`: the sandbox without namespaces (chroot, own uid, Landlock).
    * :mod:`~raykit_grading.budgets`: what a running test may hold, counted or refused: its
      memory with page tables, its disk with files that have no name, the container's memory;
      the arithmetic of the bounds.
    * :mod:`~raykit_grading.tasks`: what a test runs, the same in the grader and the sandbox.
    * :mod:`~raykit_grading.child`: what runs inside the sandbox: one task, arrays out.

Grading
    * :mod:`~raykit_grading.grade`: one submission, every test.
    * :mod:`~raykit_grading.results`: Gradescope's results.json format.
    * :mod:`~raykit_grading.batch`: a class of submissions into a CSV.
    * :mod:`~raykit_grading.intake`: what a batch takes in: folders, zips, Gradescope's export.
    * :mod:`~raykit_grading.report`: the class report, and each student's feedback page.
    * :mod:`~raykit_grading.autograder`: the Gradescope autograder zip.
    * :mod:`~raykit_grading.containers`: the zip in a real Docker container, as Gradescope
      builds and runs it (``try-zip``); the PrairieLearn image, as its grader host runs it.
    * :mod:`~raykit_grading.prairielearn`: the PrairieLearn grader image's build folder, the
      question, and PrairieLearn's results.json.

It needs a clone of the course repository: the example scenes (``scenes/``) and the hidden ones
(``grading/hidden-scenes/``) are not in any wheel.
"""

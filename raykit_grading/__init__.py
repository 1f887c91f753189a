"""raykit_grading: the instructor's autograder and the student starter kit for raykit.

``python -m raykit_grading --help`` lists the commands (:mod:`raykit_grading.__main__`). A
subpackage for each place its code runs, from what ships to students up to the platforms;
each imports only the ones listed before it (``tests/grading/test_roles.py`` reads every
import), and each module is listed here:

:mod:`~raykit_grading.kit`: ships to students, and imports nothing else of the grader
    * :mod:`~raykit_grading.kit.tasks`: what a test runs, the same in the kit, the sandbox and
      the grader.
    * :mod:`~raykit_grading.kit.compare`: arrays within a tolerance, images fairly at
      silhouettes, and the feedback shown for a failure.
    * :mod:`~raykit_grading.kit.cases`: one practice test on disk.
    * :mod:`~raykit_grading.kit.selfcheck`: the kit's ``check.py``.

:mod:`~raykit_grading.inside`: runs inside the sandbox
    * :mod:`~raykit_grading.inside.child`: one task of a submission, arrays out.

:mod:`~raykit_grading.sandbox`: the sandbox itself, on the grader's side
    * :mod:`~raykit_grading.sandbox.base`: one task in a child process, its results taken back
      as untrusted: the run every kind of sandbox shares.
    * :mod:`~raykit_grading.sandbox.returned`: the arrays a test returns, read as hostile input
      (the ``.npz`` bounded before it is parsed).
    * :mod:`~raykit_grading.sandbox.bubblewrap`: the kind in namespaces of its own (bubblewrap).
    * :mod:`~raykit_grading.sandbox.chroot`: the kind for where no namespaces can be made (a
      chroot, a uid of its own, as root).
    * :mod:`~raykit_grading.sandbox.kinds`: which kind grades here, the strongest that works.
    * :mod:`~raykit_grading.sandbox.isolation`: the bubblewrap sandbox, and the seccomp filter.
    * :mod:`~raykit_grading.sandbox.confine`: the sandbox without namespaces (chroot, own uid,
      Landlock), and the container's limits.
    * :mod:`~raykit_grading.sandbox.budgets`: what a running test may hold, counted or refused:
      its memory with page tables, its disk with files that have no name, the container's
      memory; the arithmetic of the bounds.
    * :mod:`~raykit_grading.sandbox.leftovers`: what a test's code leaves on disk, measured
      against its budget and removed whatever its shape.
    * :mod:`~raykit_grading.sandbox.workspace`: the grader's own private temporary folder.

:mod:`~raykit_grading.assignment`: the assignment as the instructor sets it
    * :mod:`~raykit_grading.assignment.catalog`: the grading tests, per stage, with points and
      visibility.
    * :mod:`~raykit_grading.assignment.seeds`: the assignment's secret seed, from which inputs
      are drawn.
    * :mod:`~raykit_grading.assignment.mistakes`: the classic mistakes, made by the reference on
      purpose.
    * :mod:`~raykit_grading.assignment.references`: the reference's results of a test's draw,
      right or with a classic mistake made.
    * :mod:`~raykit_grading.assignment.markers`: the ``# BEGIN SOLUTION`` … ``# END SOLUTION``
      regions.
    * :mod:`~raykit_grading.assignment.release`: the student release, the solution with those
      regions replaced by hints, and its practice tests.

:mod:`~raykit_grading.grading`: grading, and the class report
    * :mod:`~raykit_grading.grading.submissions`: taking a submission in, as plain files.
    * :mod:`~raykit_grading.grading.grade`: one submission, every test.
    * :mod:`~raykit_grading.grading.results`: Gradescope's results.json format.
    * :mod:`~raykit_grading.grading.options`: the options of a grading run, as ``grade``,
      ``batch`` and the platforms' entrypoints take them.
    * :mod:`~raykit_grading.grading.intake`: what a batch takes in: folders, zips, Gradescope's
      export.
    * :mod:`~raykit_grading.grading.batch`: a class of submissions into a CSV.
    * :mod:`~raykit_grading.grading.report`: the class report, and each student's feedback page.

:mod:`~raykit_grading.platforms`: where a course grades
    * :mod:`~raykit_grading.platforms.gradescope`: the Gradescope autograder zip.
    * :mod:`~raykit_grading.platforms.prairielearn`: the PrairieLearn grader image's build
      folder, the question, and PrairieLearn's results.json.
    * :mod:`~raykit_grading.platforms.containers`: the zip in a real Docker container, as
      Gradescope builds and runs it (``try-zip``); the PrairieLearn image, as its grader host
      runs it.

It needs a clone of the course repository: the example scenes (``scenes/``) and the hidden ones
(``grading/hidden-scenes/``) are not in any wheel.
"""

"""Hostile submissions, graded end to end by the real grader: each gets exactly the score it
deserves, nothing outside its sandbox is read or written, and results.json is always valid
and the grader's own.

Every test that grades through :func:`grade_as_deployed` runs in the five ways below (the
``autograder`` fixture's parameter), each skipped with its reason where this machine cannot make
it, or where another way already tests the same defences (:func:`each_defence_once`: the docker
way where the container way runs, but for :data:`EMULATION_DIFFERS`; the prairielearn way but
for :data:`PRAIRIELEARN_DIFFERS`):

* ``root``: the autograder zip's own ``run_autograder`` as root, the zip unpacked as
  Gradescope does (into ``source/``, ``run_autograder`` copied beside it, ``source/`` closed to
  everyone but root), run by a grader Python with only what ``setup.sh`` installs
  (tests/support/grader_python.py): bubblewrap's sandbox;
* ``docker``: the same ``run_autograder`` as root under an emulation of Docker's default
  confinement with a 768 MB memory limit (``tests/support/docker_confinement.py``), as
  Gradescope runs it: no namespaces, so the chroot sandbox (:mod:`raykit_grading.sandbox.confine`);
* ``user``: the README's ``python -m raykit_grading grade`` as a normal user (this one, or as
  root ``setpriv`` to uid 65534 with the same grader Python, which that uid can run);
* ``container``: the zip in a real Docker container, as Gradescope builds and runs it
  (:mod:`raykit_grading.platforms.containers`): an image built once per session from the zip on a
  base image (``RAYKIT_CONTAINER_BASE``, default the Debian one made with debootstrap, made here if
  missing), ``setup.sh`` run at build time, then a fresh container per submission with
  Docker's default seccomp profile and capabilities, 768 MB and half a CPU, the submission
  copied to ``/autograder/submission``, ``/autograder/run_autograder`` as the command: the
  chroot sandbox, for real. Skipped, saying why, where Docker cannot run containers.
* ``prairielearn``: the grader image whose build folder ``prairielearn -o`` writes
  (:mod:`raykit_grading.platforms.prairielearn`), built once per session on the same base, run as
  PrairieLearn's grader host runs it (``containers.grade_in_prairielearn_container``):
  ``/grade`` laid out as its docs say (the submission's files in ``/grade/student``, as a
  workspace question's ``gradedFiles`` sends a ``raykit/`` folder; the question's ``tests/``
  with the seed and hidden scenes), no network, its limits, the entrypoint info.json names.
  Its results.json is read back into Gradescope's shape for the same assertions
  (:func:`as_gradescope`): hidden tests are one line there (:func:`shown` says what a test's
  expected scores look like that way), and a submission that is not gradable scores nothing.

The batch tests run as the user running the suite, but for
:func:`~hostile.test_memory.test_11_a_batch_grades_honest_students_between_attackers_in_full`,
which runs ``batch`` in each way it runs on an instructor's machine (``BATCH_WAYS``). Every
attack that needs something outside its sandbox has a way to profit if it got it (it then
answers right and scores), so a defence that failed shows as a score above the one asserted.

Kinds (numbers as in the trust issue): 1 hard-coding the shipped answers, 2 links and special
files in the submission, 3 child-controlled output, 4 one broken test, 5 hidden inputs reaching
visible output, 6 reading the solution from disk, 7 forging results and killing the grader,
8 no usable child Python, 9 classmates, the network, outliving the test, 10 what one test
leaves, 11 everything a test can hold, and what is shown at once of hidden tests (issue 56:
tests/support/budget_attacks.py); and the old ones: loops, memory, forks, printing,
monkeypatching, garbage arrays.
"""

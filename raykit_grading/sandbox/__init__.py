"""The sandbox: one task of a submission run in a child process, confined, and what it hands
back read as untrusted.

:mod:`~.base` holds the run every kind shares, written once; a class for each kind,
:mod:`~.bubblewrap` and :mod:`~.chroot`; :mod:`~.kinds` chooses the strongest that works
here. Then what they are made of: the bubblewrap arguments and the seccomp filter
(:mod:`~.isolation`), the chroot tree, Landlock and the container's limits (:mod:`~.confine`), what
a running test may hold (:mod:`~.budgets`), what it leaves on disk (:mod:`~.leftovers`), the
grader's own private folder (:mod:`~.workspace`).
"""

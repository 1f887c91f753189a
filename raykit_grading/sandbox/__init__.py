"""The sandbox: one task of a submission run in a child process, confined, and what it hands
back read as untrusted.

:mod:`~.base` holds the skeleton every kind shares; a module for each kind; then what they are
made of: the bubblewrap arguments and the seccomp filter (:mod:`~.isolation`), the chroot
tree, Landlock and the container's limits (:mod:`~.confine`), what a running test may hold
(:mod:`~.budgets`), what it leaves on disk (:mod:`~.leftovers`), the grader's own private
folder (:mod:`~.workspace`).
"""

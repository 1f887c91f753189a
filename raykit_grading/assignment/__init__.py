"""The assignment as the instructor sets it: the grading tests (:mod:`~.catalog`), its secret
seed (:mod:`~.seeds`), the classic mistakes (:mod:`~.mistakes`), the solution markers
(:mod:`~.markers`), and the student release made from them (:mod:`~.release`).
"""

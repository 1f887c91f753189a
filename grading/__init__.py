"""The old name of the grader; see ``raykit_grading``."""

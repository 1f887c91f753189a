"""``python -m grading`` moved: the grader is ``python -m raykit_grading`` (named for the kit)."""

import sys

if __name__ == "__main__":
    command = " ".join(sys.argv[1:])
    print(
        f"python -m grading: the grader is now `python -m raykit_grading {command}`".rstrip(),
        file=sys.stderr,
    )
    sys.exit(2)

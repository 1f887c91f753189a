"""Grading a folder of submissions (one folder per student) on all cores.

    python -m raykit_grading batch SUBMISSIONS/ -o OUT/ [--jobs N]

writes ``OUT/scores.csv`` (student, score, max_score, then one column per test) and
``OUT/feedback/<student>/`` with that student's results.json and feedback pictures. Each
student is graded in a worker process of its own; a progress bar shows how far it has got.
"""

from __future__ import annotations

import csv
import os
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from tqdm import tqdm

from raykit_grading.catalog import by_name
from raykit_grading.grade import grade_to_file


def _grade_student(folder: Path, out: Path, options: dict) -> tuple[str, dict]:
    feedback = out / "feedback" / folder.name
    results = grade_to_file(folder, feedback / "results.json", feedback=feedback, **options)
    return folder.name, results


def grade_folder(submissions: Path, out: Path, *, jobs: int | None = None, **options) -> Path:
    """Grade every folder in ``submissions``; returns the path of scores.csv."""
    students = sorted(p for p in Path(submissions).iterdir() if p.is_dir())
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    tests = by_name(options.get("names"))
    rows = {}
    with ProcessPoolExecutor(max_workers=jobs or os.cpu_count()) as pool:
        futures = [pool.submit(_grade_student, s, out, options) for s in students]
        for future in tqdm(
            as_completed(futures), total=len(futures), unit="student", desc="grading"
        ):
            name, results = future.result()
            rows[name] = results
    path = out / "scores.csv"
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["student", "score", "max_score", *(t.name for t in tests)])
        for name in sorted(rows):
            results = rows[name]
            scores = {t["name"]: t["score"] for t in results["tests"]}
            writer.writerow(
                [
                    name,
                    results["score"],
                    sum(t.points for t in tests),
                    *(scores.get(t.name, 0) for t in tests),
                ]
            )
    print(f"wrote {path} and {out / 'feedback'}/ for {len(rows)} students")
    return path

#!/usr/bin/env python3
"""Checks that two results.csv of the same preset hold the same runs with the same results.

Usage: compare_results.py A.csv B.csv

Rows are matched by (dataset, command, algorithm, particles, refine, seed). Every metric column must be equal
(same seed and thread count give the same output), except the columns that measure time or memory (timing.*,
wall time, fps, ms per step, peak RSS, ...) and the provenance columns (machine, Slurm job id, dates, paths).
Prints each difference; exit code 0 when equal, 1 otherwise.
"""
import csv
import re
import sys

KEY = ("dataset", "command", "algorithm", "particles", "refine", "seed")
SKIP = re.compile(r"(^|\.)(timing|wall_s|cpu_s|wall_time_s|fps|ms_per_step|total_s|peak_rss_mib|git_revision|git_dirty|"
                  r"machine|cpu_model|cpu_count|slurm_job_id|started_utc|ended_utc|executable|command_line|run_dir|"
                  r"threads)($|\.)|_ms($|_|\.)|ms_median|seconds|_time")


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {tuple(r[k] for k in KEY): r for r in rows}, (rows[0].keys() if rows else [])


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a, cols_a = load(sys.argv[1])
    b, cols_b = load(sys.argv[2])
    problems = []
    if set(a) != set(b):
        problems.append(f"runs only in {sys.argv[1]}: {sorted(set(a) - set(b))}; "
                        f"only in {sys.argv[2]}: {sorted(set(b) - set(a))}")
    compared = sorted(c for c in set(cols_a) | set(cols_b) if c not in KEY and not SKIP.search(c))
    checked = 0
    for k in sorted(set(a) & set(b)):
        for c in compared:
            va, vb = a[k].get(c, ""), b[k].get(c, "")
            checked += 1
            if va != vb:
                problems.append(f"{'/'.join(k)}: {c}: {va!r} vs {vb!r}")
    for p in problems[:50]:
        print("DIFFERENT", p)
    print(f"compare_results.py: {len(set(a) & set(b))} runs, {len(compared)} columns compared "
          f"({checked} values), {len(problems)} differences")
    return 0 if not problems else 1


if __name__ == "__main__":
    sys.exit(main())

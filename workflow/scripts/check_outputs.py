#!/usr/bin/env python3
"""Checks a finished workflow output folder (OUT/PRESET): every run succeeded and is complete, the tidy CSV has
one row per run with its family's metrics and full provenance, the tables and plots exist.

Usage: check_outputs.py OUT/PRESET [--slurm]
  --slurm   also require every run to have been executed inside a Slurm job (provenance slurm_job_id)
Prints what it checked; exit code 0 when everything holds, 1 otherwise.
"""
import csv
import glob
import json
import os
import sys

PRIMARY = {"stereo": ["slam.ate.se3_rmse_m", "vo.ate.se3_rmse_m", "timing.fps", "map.landmarks"],
           "vo": ["ate.se3_rmse_m|vo.ate.se3_rmse_m"],
           "planar": ["position_rmse_m", "ms_per_step.mean"],
           "sim": ["position_rmse_m", "ms_per_step.mean"]}
PROVENANCE = ["wall_s", "peak_rss_mib", "git_revision", "machine", "started_utc", "command_line"]


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    slurm = "--slurm" in sys.argv[1:]
    if len(args) != 1:
        sys.exit(__doc__)
    out = args[0]
    errors = []
    provs = sorted(glob.glob(os.path.join(out, "runs", "**", "provenance.json"), recursive=True))
    expected_rows = 0
    for p in provs:
        d = os.path.dirname(p)
        prov = json.load(open(p))
        if prov.get("exit_code") != 0:
            errors.append(f"{d}: exit code {prov.get('exit_code')}")
        if not os.path.isfile(os.path.join(d, "metrics.json")):
            errors.append(f"{d}: no metrics.json")
            continue
        m = json.load(open(os.path.join(d, "metrics.json")))
        if m.get("interrupted"):
            errors.append(f"{d}: interrupted run")
        expected_rows += len(m.get("position_rmse_each_run_m", [])) if prov.get("command") == "sim" else 1
        if prov.get("command") == "run" and m.get("slam") is not None:
            for f in ("trajectory.txt", "vo_trajectory.txt", "map.pcd", "config_used.yaml"):
                if not os.path.isfile(os.path.join(d, f)):
                    errors.append(f"{d}: {f} missing")
        if slurm and not prov.get("slurm_job_id"):
            errors.append(f"{d}: not run inside a Slurm job")
    print(f"check_outputs: {len(provs)} jobs with provenance, all exit code 0: "
          f"{not any('exit code' in e for e in errors)}")
    with open(os.path.join(out, "results.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    if len(rows) != expected_rows:
        errors.append(f"results.csv has {len(rows)} rows, expected {expected_rows} (one per run)")
    fam_count = {}
    for r in rows:
        fam = ("sim" if r["command"] == "sim" else "vo" if r["command"] == "vo"
               else "stereo" if r.get("slam.ate.se3_rmse_m") else "planar")
        fam_count[fam] = fam_count.get(fam, 0) + 1
        for col in PRIMARY[fam] + PROVENANCE:
            if not any(r.get(c) for c in col.split("|")):
                errors.append(f"row {r['dataset']}/{r['command']}/{r['algorithm']}/N={r['particles']}/"
                              f"seed {r['seed']}: empty {col}")
        if slurm and not r.get("slurm_job_id"):
            errors.append(f"row {r['dataset']}/{r['algorithm']}/seed {r['seed']}: no Slurm job id")
    print(f"check_outputs: results.csv {len(rows)} rows (expected {expected_rows}), per family {fam_count}")
    summary = open(os.path.join(out, "summary.md")).read()
    tables = summary.count("\n## ")
    if tables != len(fam_count):
        errors.append(f"summary.md has {tables} tables, expected {len(fam_count)} (one per family)")
    for f in ("summary.html", "results.md", "resources_measured.yaml", "plots/slam_vs_vo.png",
              "plots/rmse_vs_particles.png", "plots/time_vs_particles.png", "plots/rfs_vs_vector_ml.png"):
        path = os.path.join(out, f)
        if not os.path.isfile(path) or os.path.getsize(path) < 200:
            errors.append(f"{f} missing or empty")
        elif f.endswith(".png") and open(path, "rb").read(8) != b"\x89PNG\r\n\x1a\n":
            errors.append(f"{f} is not a PNG")
    print(f"check_outputs: summary.md {tables} tables; summary.html, results.md, resources_measured.yaml, 4 plots "
          f"checked")
    for e in errors[:40]:
        print("ERROR", e)
    print("check_outputs:", "OK" if not errors else f"{len(errors)} errors")
    return 0 if not errors else 1


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Aggregates the workflow's runs: one tidy CSV row per run, summary tables (mean ± std over seeds), the results
document and the measured resources.

Usage: aggregate.py --runs DIR --preset NAME --csv FILE --summary-md FILE --summary-html FILE --results-md FILE
                    --resources FILE PROVENANCE.json...

Each PROVENANCE.json (written by run_one.py) sits beside the run's metrics.json. A row holds the run's identity
(dataset, command, algorithm, particles, refine, seed), every scalar of metrics.json flattened with dots
(slam.kitti.t_rel_percent, timing.fps, position_rmse_m, ...), and its provenance (wall time, peak RSS, git revision,
machine, Slurm job id, ...). A `glmbslam sim` job covering several Monte Carlo runs gives one row per run: its
position_rmse_m and gospa_m are that run's (seed = run index); its other metric columns are the job's.
Only the Python standard library is used.
"""
import argparse
import csv
import html
import json
import math
import os
import statistics
import sys

ID_COLUMNS = ["preset", "dataset", "command", "algorithm", "particles", "refine", "seed", "scenario", "clutter",
              "frame_range", "config_file", "threads"]
PROVENANCE_COLUMNS = ["wall_s", "cpu_s", "peak_rss_mib", "runs_in_job", "git_revision", "git_dirty", "machine", "cpu_model",
                      "cpu_count", "slurm_job_id", "openblas_num_threads", "started_utc", "ended_utc", "executable",
                      "command_line",
                      "run_dir"]
GROUP = ["dataset", "command", "algorithm", "particles", "refine"]

# Summary tables: (title, predicate on a group's rows, [(column header, CSV column)]).
STEREO_COLUMNS = [
    ("SLAM t_rel %", "slam.kitti.t_rel_percent"), ("SLAM r_rel deg/100m", "slam.kitti.r_rel_deg_per_100m"),
    ("SLAM ATE m", "slam.ate.se3_rmse_m"), ("SLAM drift %", "slam.end_point_drift_percent"),
    ("refined t_rel %", "refined.kitti.t_rel_percent"), ("refined ATE m", "refined.ate.se3_rmse_m"),
    ("VO t_rel %", "vo.kitti.t_rel_percent"), ("VO r_rel deg/100m", "vo.kitti.r_rel_deg_per_100m"),
    ("VO ATE m", "vo.ate.se3_rmse_m"), ("VO drift %", "vo.end_point_drift_percent"),
    ("fps", "timing.fps"), ("backend ms", "timing.backend_ms_median"), ("landmarks", "map.landmarks"),
    ("ESS %", "filter.ess_percent"), ("peak RSS MiB", "peak_rss_mib"), ("wall s", "wall_s"), ("CPU s", "cpu_s"),
]
VO_COLUMNS = [
    ("t_rel %", "kitti.t_rel_percent"), ("r_rel deg/100m", "kitti.r_rel_deg_per_100m"),
    ("ATE m", "ate.se3_rmse_m"), ("drift %", "drift.end_point_error_percent"),
    ("t_rel %", "vo.kitti.t_rel_percent"), ("r_rel deg/100m", "vo.kitti.r_rel_deg_per_100m"),
    ("ATE m", "vo.ate.se3_rmse_m"), ("drift %", "vo.end_point_drift_percent"),
    ("peak RSS MiB", "peak_rss_mib"), ("wall s", "wall_s"), ("CPU s", "cpu_s"),
]
PLANAR_COLUMNS = [
    ("position RMSE m", "position_rmse_m"), ("refined position RMSE m", "refined.position_rmse_m"),
    ("ms per step", "ms_per_step.mean"), ("ESS %", "ess_percent"),
    ("resampling %", "resampling_percent"), ("landmarks", "map.landmarks"), ("peak RSS MiB", "peak_rss_mib"),
    ("wall s", "wall_s"), ("CPU s", "cpu_s"),
]
SIM_COLUMNS = [
    ("position RMSE m (per run)", "position_rmse_m"), ("GOSPA m (per run)", "gospa_m"),
    ("final OSPA m (job mean)", "ospa.final_m.mean"),
    ("ms per step", "ms_per_step.mean"), ("ESS %", "ess_percent"), ("resampling %", "resampling_percent"),
]


def flatten(obj, prefix="", out=None):
    out = {} if out is None else out
    if isinstance(obj, dict):
        for k, v in obj.items():
            flatten(v, f"{prefix}{k}.", out)
    elif isinstance(obj, (int, float, str, bool)) or obj is None:
        out[prefix[:-1]] = obj
    return out  # lists (per-step and per-run series) are left out


def rows_of_run(prov_path):
    with open(prov_path) as f:
        prov = json.load(f)
    run_dir = os.path.dirname(prov_path)
    with open(os.path.join(run_dir, "metrics.json")) as f:
        metrics = json.load(f)
    base = {k: prov.get(k) for k in ID_COLUMNS if k in prov}
    for k in ("wall_s", "cpu_s", "peak_rss_mib", "git_revision", "git_dirty", "machine", "cpu_model", "cpu_count",
              "slurm_job_id", "openblas_num_threads", "started_utc", "ended_utc", "executable"):
        base[k] = prov.get(k)
    base["command_line"] = " ".join(prov.get("argv", []))
    base["run_dir"] = run_dir
    flat = flatten(metrics)
    for k in list(flat):
        if k in base or k in ("seed", "particles", "algorithm", "scenario", "runs", "first_run", "threads"):
            flat.pop(k)  # identity columns come from the workflow, not from the program's echo of them
    if prov.get("command") == "sim" and "position_rmse_each_run_m" in metrics:
        per_run = metrics["position_rmse_each_run_m"]
        gospa = metrics.get("gospa", {}).get("distance_each_run_m", [None] * len(per_run))
        first = prov.get("first_run", 0)
        rows = []
        for i, v in enumerate(per_run):
            row = dict(base, **flat)
            row["seed"] = first + i
            row["position_rmse_m"] = v
            row["gospa_m"] = gospa[i] if i < len(gospa) else None
            row["runs_in_job"] = len(per_run)
            rows.append(row)
        return rows
    row = dict(base, **flat)
    row["runs_in_job"] = 1
    return [row]


def number(v):
    if v is None or v == "" or isinstance(v, bool):
        return None
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def decimals_for(x):
    if x == 0:
        return 3
    return max(0, 3 - int(math.floor(math.log10(abs(x)))))


def mean_std(values):
    v = [x for x in (number(y) for y in values) if x is not None]
    if not v:
        return ""
    m = statistics.fmean(v)
    d = min(decimals_for(m), 6)
    if len(v) == 1:
        return f"{m:.{d}f}"
    return f"{m:.{d}f} ± {statistics.stdev(v):.{d}f}"


def family(rows):
    r = rows[0]
    if r.get("command") == "sim":
        return "sim"
    if r.get("command") == "vo":
        return "vo"
    if any(k.startswith("slam.") for k in r):
        return "stereo"
    return "planar"


TABLES = [("stereo", "Stereo SLAM (glmbslam run) and its VO input", STEREO_COLUMNS),
          ("vo", "Stereo visual odometry (glmbslam vo)", VO_COLUMNS),
          ("planar", "Victoria Park and other 2D datasets (glmbslam run)", PLANAR_COLUMNS),
          ("sim", "Monte Carlo simulations (glmbslam sim)", SIM_COLUMNS)]


def group_key(row):
    return tuple(str(row.get(k, "")) for k in GROUP)


def sort_key(key):
    ds, cmd, alg, n, ref = key
    return (ds, cmd, alg, int(n) if n.isdigit() else 0, ref)


def build_tables(rows):
    groups = {}
    for r in rows:
        groups.setdefault(group_key(r), []).append(r)
    tables = []
    for fam, title, columns in TABLES:
        keys = sorted((k for k, g in groups.items() if family(g) == fam), key=sort_key)
        if not keys:
            continue
        # Keep the columns some group of this family has; the VO table's two spellings collapse into one.
        present = []
        for header, col in columns:
            if any(number(r.get(col)) is not None for k in keys for r in groups[k]):
                if header not in [h for h, _ in present]:
                    present.append((header, [col]))
                else:
                    dict(present)[header].append(col)
        headers = ["dataset", "algorithm", "N", "refine", "runs"] + [h for h, _ in present]
        body = []
        for k in keys:
            g = groups[k]
            cells = [k[0], k[2], k[3] if fam != "vo" else "", k[4] if fam != "vo" else "", str(len(g))]
            for _, cols in present:
                cell = ""
                for col in cols:
                    cell = mean_std([r.get(col) for r in g])
                    if cell:
                        break
                cells.append(cell)
            body.append(cells)
        tables.append((title, headers, body))
    return tables


def markdown_table(headers, body):
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(c if c else "–" for c in cells) + " |" for cells in body]
    return "\n".join(lines)


def provenance_text(rows, preset):
    revs = sorted({str(r.get("git_revision"))[:12] + (" (modified)" if r.get("git_dirty") else "")
                   for r in rows})
    machines = sorted({str(r.get("machine")) for r in rows})
    cpus = sorted({str(r.get("cpu_model")) for r in rows})
    dates = sorted(str(r.get("started_utc"))[:10] for r in rows if r.get("started_utc"))
    slurm = sum(1 for r in rows if r.get("slurm_job_id"))
    jobs = {r["run_dir"] for r in rows}
    per_job = {r["run_dir"]: r for r in rows}.values()
    wall = sum(number(r.get("wall_s")) or 0 for r in per_job)
    cpu = sum(number(r.get("cpu_s")) or 0 for r in per_job)
    return (f"Preset `{preset}`: {len(rows)} runs in {len(jobs)} jobs ({slurm} rows from Slurm jobs), "
            f"{wall / 60:.1f} min of job wall time, {cpu / 60:.1f} min CPU; dates {dates[0] if dates else '?'} to "
            f"{dates[-1] if dates else '?'}; git revision {', '.join(revs)}; machine {', '.join(machines)} "
            f"({'; '.join(cpus)}). Mean ± sample standard deviation over seeds (simulations: over Monte Carlo "
            f"runs); t_rel / r_rel are the KITTI devkit metric (empty when the run is shorter than its 100 m "
            f"segments), ATE the SE(3)-aligned RMSE.")


def write_markdown(path, tables, intro):
    parts = [intro, ""]
    for title, headers, body in tables:
        parts += [f"## {title}", "", markdown_table(headers, body), ""]
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(parts))
    os.replace(path + ".tmp", path)


def write_html(path, tables, intro, preset):
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'>",
             f"<title>glmbslam results ({html.escape(preset)})</title>",
             "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse;margin-bottom:2em}"
             "td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}td:first-child,th{text-align:left}"
             "th{background:#eee}img{max-width:48%;margin:0.5%}</style></head><body>",
             f"<h1>glmbslam results: preset {html.escape(preset)}</h1>", f"<p>{html.escape(intro)}</p>"]
    for title, headers, body in tables:
        parts.append(f"<h2>{html.escape(title)}</h2><table><tr>" +
                     "".join(f"<th>{html.escape(h)}</th>" for h in headers) + "</tr>")
        for cells in body:
            parts.append("<tr>" + "".join(f"<td>{html.escape(c) if c else '–'}</td>" for c in cells) + "</tr>")
        parts.append("</table>")
    parts.append("<h2>Plots</h2>")
    for name in ("slam_vs_vo", "rmse_vs_particles", "time_vs_particles"):
        parts.append(f"<img src='plots/{name}.png' alt='{name}'>")
    parts.append("</body></html>\n")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(parts))
    os.replace(path + ".tmp", path)


def write_resources(path, rows):
    """Measured peak RSS and wall time per dataset and command, with the config values they suggest."""
    jobs = {r["run_dir"]: r for r in rows}.values()
    per = {}
    for r in jobs:
        k = (r["dataset"], r["command"])
        rss, wall = number(r.get("peak_rss_mib")) or 0, number(r.get("wall_s")) or 0
        runs = int(r.get("runs_in_job") or 1)
        p = per.setdefault(k, {"jobs": 0, "peak_rss_mib": 0.0, "wall_s": 0.0, "wall_s_per_run": 0.0})
        p["jobs"] += 1
        p["peak_rss_mib"] = max(p["peak_rss_mib"], rss)
        p["wall_s"] = max(p["wall_s"], wall)
        p["wall_s_per_run"] = max(p["wall_s_per_run"], wall / runs)
    lines = ["# Measured by the workflow's aggregate: the largest peak RSS and wall time of each dataset's jobs,",
             "# and the resources they suggest for config.yaml (mem_mb: 1.5 x peak RSS + 100 MB;",
             "# runtime: 3 x the wall time per job (sim: per Monte Carlo run) in minutes, at least 1).",
             "measured:"]
    for (ds, cmd), p in sorted(per.items()):
        mem = int(math.ceil(1.5 * p["peak_rss_mib"] * 1.048576 + 100))
        rt = max(1, int(math.ceil(3 * (p["wall_s_per_run"] if cmd == "sim" else p["wall_s"]) / 60)))
        lines.append(f"  {ds}/{cmd}: {{jobs: {p['jobs']}, peak_rss_mib: {p['peak_rss_mib']:.1f}, "
                     f"wall_s: {p['wall_s']:.1f}, suggested_mem_mb: {mem}, suggested_runtime_min: {rt}}}")
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", required=True)
    ap.add_argument("--preset", required=True)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--summary-md", required=True)
    ap.add_argument("--summary-html", required=True)
    ap.add_argument("--results-md", required=True)
    ap.add_argument("--resources", required=True)
    ap.add_argument("provenance", nargs="+")
    a = ap.parse_args()

    rows = []
    for p in a.provenance:
        rows += rows_of_run(p)
    rows.sort(key=lambda r: (sort_key(group_key(r)), int(r.get("seed") or 0)))
    metric_cols = sorted({k for r in rows for k in r} - set(ID_COLUMNS) - set(PROVENANCE_COLUMNS))
    columns = ID_COLUMNS + metric_cols + PROVENANCE_COLUMNS
    with open(a.csv + ".tmp", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in columns})
    os.replace(a.csv + ".tmp", a.csv)

    tables = build_tables(rows)
    intro = provenance_text(rows, a.preset)
    write_markdown(a.summary_md, tables, f"# glmbslam results: preset {a.preset}\n\n{intro}")
    regenerate = ("snakemake --cores 2 --config preset=" + a.preset +
                  (" && snakemake --cores 1 --forcerun results_doc results_doc --config preset=" + a.preset))
    write_markdown(a.results_md, tables,
                   "# Results\n\nGenerated by the experiment workflow (`workflow/`) from one tidy table of every run "
                   f"(`results.csv` in its output folder); do not edit by hand. Regenerate with `{regenerate}`.\n\n"
                   + intro)
    write_html(a.summary_html, tables, intro, a.preset)
    write_resources(a.resources, rows)
    print(f"aggregate.py: {len(rows)} rows, {len(columns)} columns -> {a.csv}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

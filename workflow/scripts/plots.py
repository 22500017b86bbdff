#!/usr/bin/env python3
"""Comparison plots from the workflow's tidy results.csv (matplotlib, Debian's python3-matplotlib).

Usage: plots.py RESULTS.csv SLAM_VS_VO.png RMSE_VS_PARTICLES.png TIME_VS_PARTICLES.png RFS_VS_VECTOR_ML.png

- SLAM vs VO per sequence: for every stereo dataset, the SLAM estimate of each (algorithm, N, refine) next to its
  own VO input (the `vo.*` block of the same runs) and `glmbslam vo` when run: KITTI t_rel (left) and ATE (right),
  mean over seeds with the standard deviation as error bar.
- RMSE vs particle count: per dataset and algorithm, the primary error (stereo: SLAM ATE; 2D: position RMSE).
- Time vs particle count: stereo: ms per frame end to end (1000 / fps); 2D and simulations: ms per step.
- RFS-ML vs vector ML (paper 004's claim): on the paper004_1d scenario, `--algorithm mlslam` with the RFS
  likelihood (Eq. 7) and with nearest-neighbour association (Eq. 4), against the clutter rate: position RMSE per
  run (mean ± std, dead reckoning for reference), map OSPA and cardinality error (job means).
A plot without data says so in its frame instead of being left out, so the outputs always exist.
"""
import csv
import math
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def num(v):
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def stats(values):
    v = [x for x in values if x is not None]
    if not v:
        return None, None
    return statistics.fmean(v), (statistics.stdev(v) if len(v) > 1 else 0.0)


def empty(path, text):
    fig, ax = plt.subplots(figsize=(6, 3))
    ax.text(0.5, 0.5, text, ha="center", va="center")
    ax.set_axis_off()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def is_stereo(r):
    return r["command"] == "run" and any(num(r.get(k)) is not None for k in ("slam.ate.se3_rmse_m",))


def slam_vs_vo(rows, path):
    stereo = [r for r in rows if is_stereo(r) or (r["command"] == "vo")]
    datasets = sorted({r["dataset"] for r in stereo})
    if not datasets:
        empty(path, "no stereo runs in this preset")
        return
    metrics = [("KITTI t_rel (%)", "t_rel"), ("ATE SE(3) (m)", "ate")]
    col = {"t_rel": ("slam.kitti.t_rel_percent", "vo.kitti.t_rel_percent", "kitti.t_rel_percent"),
           "ate": ("slam.ate.se3_rmse_m", "vo.ate.se3_rmse_m", "ate.se3_rmse_m")}
    fig, axes = plt.subplots(1, 2, figsize=(max(8, 2.2 * len(datasets) + 4), 4.5))
    for ax, (label, key) in zip(axes, metrics):
        slam_col, vo_col, vo_cmd_col = col[key]
        series = {}  # name -> {dataset: [values]}
        for r in stereo:
            if r["command"] == "run":
                name = f"SLAM {r['algorithm']} N={r['particles']}" + (
                    f" refine {r['refine']}" if r["refine"] != "none" else "")
                series.setdefault(name, {}).setdefault(r["dataset"], []).append(num(r.get(slam_col)))
                if r["refine"] != "none" and num(r.get(slam_col.replace("slam.", "refined."))) is not None:
                    series.setdefault(name + " (refined)", {}).setdefault(r["dataset"], []).append(
                        num(r.get(slam_col.replace("slam.", "refined."))))
                series.setdefault("its VO input", {}).setdefault(r["dataset"], []).append(num(r.get(vo_col)))
            else:
                series.setdefault("glmbslam vo", {}).setdefault(r["dataset"], []).append(
                    num(r.get(vo_cmd_col)) if num(r.get(vo_cmd_col)) is not None else num(r.get(vo_col)))
        names = sorted(series, key=lambda n: (not n.startswith("SLAM"), n))
        width = 0.8 / max(1, len(names))
        plotted = False
        for i, name in enumerate(names):
            xs, ms, ss = [], [], []
            for j, ds in enumerate(datasets):
                m, s = stats(series[name].get(ds, []))
                if m is not None:
                    xs.append(j + (i - (len(names) - 1) / 2) * width)
                    ms.append(m)
                    ss.append(s)
            if xs:
                ax.bar(xs, ms, width, yerr=ss, capsize=2, label=name)
                plotted = True
        ax.set_xticks(range(len(datasets)))
        ax.set_xticklabels(datasets, rotation=30, ha="right")
        ax.set_ylabel(label)
        if plotted:
            ax.legend(fontsize=7)
        else:
            ax.text(0.5, 0.5, "no value (runs shorter than the\nKITTI metric's 100 m segments)",
                    ha="center", va="center", transform=ax.transAxes)
    fig.suptitle("SLAM vs VO per sequence (mean ± std over seeds)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def versus_particles(rows, path, value_of, ylabel, title):
    curves = {}  # (dataset, command) -> {(algorithm, refine): {N: [values]}}
    stereo = set()
    for r in rows:
        if r["command"] == "vo":
            continue
        v = value_of(r)
        if v is None:
            continue
        if is_stereo(r):
            stereo.add((r["dataset"], r["command"]))
        curves.setdefault((r["dataset"], r["command"]), {}).setdefault((r["algorithm"], r["refine"]), {}) \
            .setdefault(int(r["particles"]), []).append(v)
    panels = sorted(k for k, c in curves.items() if any(len(n) > 1 for n in c.values()))
    if not panels:
        empty(path, "no algorithm was run with more than one particle count")
        return
    cols = min(3, len(panels))
    nrows = int(math.ceil(len(panels) / cols))
    fig, axes = plt.subplots(nrows, cols, figsize=(5 * cols, 3.8 * nrows), squeeze=False)
    for ax, key in zip(axes.flat, panels):
        all_n = sorted({n for by_n in curves[key].values() for n in by_n})
        for (alg, refine), by_n in sorted(curves[key].items()):
            ns = sorted(by_n)
            ms = [stats(by_n[n])[0] for n in ns]
            ss = [stats(by_n[n])[1] for n in ns]
            ax.errorbar(ns, ms, yerr=ss, marker="o", capsize=3,
                        label=alg + (f" refine {refine}" if refine != "none" else ""))
        ax.set_xscale("log")
        ax.minorticks_off()
        ax.set_xticks(all_n)
        ax.set_xticklabels([str(n) for n in all_n])
        ax.set_xlabel("particles N")
        ax.set_ylabel(ylabel[0] if key in stereo else ylabel[1])
        ax.set_title(f"{key[0]} ({key[1]})", fontsize=9)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[len(panels):]:
        ax.set_axis_off()
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def error_value(r):
    """The run's final estimate: the refined one with --refine (sim writes it as position_rmse_m)."""
    refined = r.get("refine", "none") not in ("none", "", None)
    if is_stereo(r):
        return num(r.get("refined.ate.se3_rmse_m" if refined else "slam.ate.se3_rmse_m"))
    if refined and num(r.get("refined.position_rmse_m")) is not None:
        return num(r.get("refined.position_rmse_m"))
    return num(r.get("position_rmse_m"))


def time_value(r):
    if is_stereo(r):
        fps = num(r.get("timing.fps"))
        return 1000.0 / fps if fps else None
    return num(r.get("ms_per_step.mean"))


def rfs_vs_vector_ml(rows, path):
    # (association, clutter rate) -> per-run position RMSE, job means of map OSPA and cardinality error
    rmse, ospa, card, dr = {}, {}, {}, {}
    for r in rows:
        if r.get("command") != "sim" or r.get("scenario") != "paper004_1d" or r.get("algorithm") != "mlslam":
            continue
        lam = num(r.get("clutter_rate"))
        if lam is None:
            continue
        key = (r.get("association") or "rfs", lam)
        rmse.setdefault(key, []).append(num(r.get("position_rmse_m")))
        ospa.setdefault(key, {})[r["run_dir"]] = num(r.get("map_ospa.distance_m.mean"))
        card.setdefault(key, {})[r["run_dir"]] = num(r.get("cardinality_error.mean"))
        dr.setdefault(lam, {})[r["run_dir"]] = num(r.get("dead_reckoning_rmse_per_run_m.mean"))
    if not rmse:
        empty(path, "no paper004_1d mlslam runs (RFS-ML vs vector ML)")
        return
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    labels = {"rfs": "RFS-ML (Eq. 7)", "nearest_neighbour": "vector ML, nearest neighbour (Eq. 4)"}
    for assoc in sorted({a for a, _ in rmse}):
        lams = sorted(lam for a, lam in rmse if a == assoc)
        label = labels.get(assoc, assoc)
        m = [stats(rmse[(assoc, x)]) for x in lams]
        axes[0].errorbar(lams, [v[0] for v in m], yerr=[v[1] for v in m], marker="o", capsize=3, label=label)
        for ax, per_job in ((axes[1], ospa), (axes[2], card)):
            ax.plot(lams, [stats(list(per_job[(assoc, x)].values()))[0] for x in lams], marker="o", label=label)
    lams = sorted(dr)
    axes[0].plot(lams, [stats(list(dr[x].values()))[0] for x in lams], "k--", label="dead reckoning")
    for ax, ylabel in zip(axes, ("position RMSE per run (m)", "map OSPA, c = 1 m (m)", "cardinality error")):
        ax.set_xlabel("clutter rate λ_c per scan")
        ax.set_ylabel(ylabel)
        ax.legend(fontsize=7)
    fig.suptitle("Paper 004's 1D problem: RFS-ML against vector ML under clutter (mean over runs)")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    slam_vs_vo(rows, sys.argv[2])
    versus_particles(rows, sys.argv[3], error_value, ("SLAM ATE SE(3) (m)", "position RMSE (m)"),
                     "Error vs particle count (mean ± std over seeds / runs)")
    versus_particles(rows, sys.argv[4], time_value, ("ms per frame (1000 / fps)", "ms per step"),
                     "Time vs particle count (mean ± std)")
    rfs_vs_vector_ml(rows, sys.argv[5])
    return 0


if __name__ == "__main__":
    sys.exit(main())

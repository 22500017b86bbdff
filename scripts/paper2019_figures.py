#!/usr/bin/env python3
"""Paper 000's comparison figures from `glmbslam sim --scenario paper2019` runs (standard library only).

Reads OUT/<algorithm>_clutter<λ>/metrics.json for every algorithm and clutter rate and writes, per clutter rate,
SVG line charts over the time steps with one line per algorithm:
  position_error_clutter<λ>.svg   RMS position error over the Monte Carlo runs (√(RMSE_x² + RMSE_y²))
  heading_error_clutter<λ>.svg    RMS heading error
  ospa_clutter<λ>.svg             mean map OSPA (c = 0.5 m, p = 1)
  gospa_clutter<λ>.svg            mean map GOSPA (c = 0.5 m, p = 1, α = 2)
  cardinality_clutter<λ>.svg      mean estimated number of landmarks, and the true number seen so far
and OUT/comparison.md, the table of means over the time steps and runs.

Usage: paper2019_figures.py OUT "glmb2 glmb1 lmb phd1" "1 5 10 15"
"""
import json
import math
import os
import sys

COLOURS = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f"]
NAMES = {"glmb2": "δ-GLMB-SLAM 2.0", "glmb1": "δ-GLMB-SLAM 1.0", "lmb": "LMB-SLAM (optimal kernel)",
         "lmb1": "LMB-SLAM (prior)", "phd1": "RB-PHD-SLAM 1.0", "phd3": "PHD-SLAM 3.0",
         "fastslam2": "FastSLAM 2.0 (ML)", "fastslam2-known": "FastSLAM 2.0 (known)", "glmb_mh": "δ-GLMB + MH-ID"}


def nice_ticks(lo, hi, n=5):
    if hi <= lo:
        hi = lo + 1.0
    raw = (hi - lo) / n
    mag = 10 ** math.floor(math.log10(raw))
    step = min((s * mag for s in (1, 2, 2.5, 5, 10) if s * mag >= raw), default=raw)
    first = math.floor(lo / step) * step
    ticks = []
    t = first
    while t <= hi + 1e-9 * step:
        ticks.append(t)
        t += step
    return ticks


def svg_lines(path, title, xlabel, ylabel, series, width=900, height=520):
    """series: list of (label, colour, xs, ys, dashed)."""
    left, right, top, bottom = 80, 230, 50, 60
    xs_all = [x for s in series for x in s[2]]
    ys_all = [y for s in series for y in s[3] if math.isfinite(y)]
    if not xs_all or not ys_all:
        return
    xt = nice_ticks(min(xs_all), max(xs_all))
    yt = nice_ticks(min(0.0, min(ys_all)), max(ys_all))
    x0, x1, y0, y1 = xt[0], xt[-1], yt[0], yt[-1]
    pw, ph = width - left - right, height - top - bottom

    def px(x):
        return left + (x - x0) / (x1 - x0) * pw

    def py(y):
        return top + ph - (y - y0) / (y1 - y0) * ph

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" '
           f'font-size="13">', f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{left + pw / 2}" y="25" text-anchor="middle" font-size="16">{title}</text>']
    for t in xt:
        out.append(f'<line x1="{px(t):.1f}" y1="{top}" x2="{px(t):.1f}" y2="{top + ph}" stroke="#ddd"/>')
        out.append(f'<text x="{px(t):.1f}" y="{top + ph + 18}" text-anchor="middle">{t:g}</text>')
    for t in yt:
        out.append(f'<line x1="{left}" y1="{py(t):.1f}" x2="{left + pw}" y2="{py(t):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{py(t) + 4:.1f}" text-anchor="end">{t:g}</text>')
    out.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="black"/>')
    out.append(f'<text x="{left + pw / 2}" y="{height - 15}" text-anchor="middle">{xlabel}</text>')
    out.append(f'<text transform="translate(20,{top + ph / 2}) rotate(-90)" text-anchor="middle">{ylabel}</text>')
    for i, (label, colour, xs, ys, dashed) in enumerate(series):
        pts = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in zip(xs, ys) if math.isfinite(y))
        dash = ' stroke-dasharray="6,4"' if dashed else ""
        out.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="1.6"{dash}/>')
        ly = top + 20 + 22 * i
        out.append(f'<line x1="{left + pw + 15}" y1="{ly}" x2="{left + pw + 45}" y2="{ly}" stroke="{colour}" '
                   f'stroke-width="2"{dash}/>')
        out.append(f'<text x="{left + pw + 52}" y="{ly + 4}">{label}</text>')
    out.append("</svg>")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out))


def main():
    out, algorithms, rates = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
    rows = []
    for lam in rates:
        pos, head, ospa, gospa, card = [], [], [], [], []
        truth = None
        for i, alg in enumerate(algorithms):
            path = os.path.join(out, f"{alg}_clutter{lam}", "metrics.json")
            if not os.path.exists(path):
                print(f"missing {path}", file=sys.stderr)
                continue
            with open(path, encoding="utf-8") as f:
                m = json.load(f)
            colour = COLOURS[i % len(COLOURS)]
            name = NAMES.get(alg, alg)
            r = m["rmse_per_step"]
            steps = list(range(len(r["x_m"])))
            perr = [math.hypot(a, b) for a, b in zip(r["x_m"], r["y_m"])]
            pos.append((name, colour, steps, perr, False))
            head.append((name, colour, steps, r["heading_deg"], False))
            o = m["ospa"]
            k1 = list(range(1, len(o["per_step_mean_m"]) + 1))
            ospa.append((name, colour, k1, o["per_step_mean_m"], False))
            gospa.append((name, colour, k1, o["per_step_gospa_mean_m"], False))
            c = m["cardinality_per_step"]
            card.append((name, colour, k1, c["estimated_mean"], False))
            truth = (k1, c["true"])
            rows.append((lam, alg, m["position_rmse_m"], m["heading_rmse_deg"], o["mean_over_steps_m"],
                         o["gospa_mean_over_steps_m"],
                         sum(c["estimated_mean"]) / max(1, len(c["estimated_mean"])) -
                         sum(c["true"]) / max(1, len(c["true"])),
                         m["ms_per_step"]["mean"], m["runs"], m["particles"]))
        if truth is not None:
            card.append(("true (seen so far)", "black", truth[0], truth[1], True))
        tag = f"λc = {lam}"
        svg_lines(os.path.join(out, f"position_error_clutter{lam}.svg"), f"RMS position error ({tag})", "time step",
                  "position error [m]", pos)
        svg_lines(os.path.join(out, f"heading_error_clutter{lam}.svg"), f"RMS heading error ({tag})", "time step",
                  "heading error [deg]", head)
        svg_lines(os.path.join(out, f"ospa_clutter{lam}.svg"), f"Mean map OSPA, c = 0.5 m, p = 1 ({tag})",
                  "time step", "OSPA [m]", ospa)
        svg_lines(os.path.join(out, f"gospa_clutter{lam}.svg"), f"Mean map GOSPA, c = 0.5 m, p = 1, α = 2 ({tag})",
                  "time step", "GOSPA [m]", gospa)
        svg_lines(os.path.join(out, f"cardinality_clutter{lam}.svg"), f"Estimated number of landmarks ({tag})",
                  "time step", "landmarks", card)
    with open(os.path.join(out, "comparison.md"), "w", encoding="utf-8") as f:
        if rows:
            f.write(f"# paper2019 comparison: {rows[0][8]} runs, {rows[0][9]} particles\n\n")
        f.write("| λ_c | algorithm | position RMSE (m) | heading RMSE (deg) | mean OSPA (m) | mean GOSPA (m) | "
                "mean cardinality error | ms/step |\n|---|---|---|---|---|---|---|---|\n")
        for lam, alg, p, h, o, g, c, t, _, _ in rows:
            f.write(f"| {lam} | {alg} | {p:.3f} | {h:.3f} | {o:.3f} | {g:.3f} | {c:+.2f} | {t:.2f} |\n")
    with open(os.path.join(out, "comparison.md"), encoding="utf-8") as f:
        print(f.read(), end="")


if __name__ == "__main__":
    main()

#!/usr/bin/env bash
# Stereo δ-GLMB-SLAM over seeds and particle counts on one KITTI sequence or drive: for every particle count, the
# mean ± std over seeds of the SLAM and VO ATE SE(3), end-point drift, KITTI t_rel / r_rel (when the sequence is
# long enough for 100 m segments), fps end to end, ESS and resampling percentages, from `glmbslam run` (one run
# per seed, each writing metrics.json). The issue-7 comparison "SLAM beats its own VO input" reads off this table.
#
# Usage: scripts/stereo_table.sh [DATASET] [OUT_DIR]
#   DATASET    KITTI odometry sequences/XX or KITTI raw drive folder
#              (default ../shared/data/kitti_raw/2011_09_26/2011_09_26_drive_0001_sync)
#   OUT_DIR    where runs and table.md go (default out/stereo_table)
# Environment:
#   GLMBSLAM   the executable (default build/src/app/glmbslam)
#   CONFIG     config file (default config/kitti_raw.yaml)
#   PARTICLES  default "1 10" (the configs' default and paper 000's count; "1 10 50" for the real-time figures)
#   SEEDS      default "0 1 2 3 4"
#   FRAMES     optional frame range A:B
#   THREADS    worker threads per run (default: all cores; runs are sequential so fps is end to end)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data="${1:-$root/../shared/data/kitti_raw/2011_09_26/2011_09_26_drive_0001_sync}"
out="${2:-$root/out/stereo_table}"
bin="${GLMBSLAM:-$root/build/src/app/glmbslam}"
config="${CONFIG:-$root/config/kitti_raw.yaml}"
particles="${PARTICLES:-1 10}"
seeds="${SEEDS:-0 1 2 3 4}"
[ -d "$data" ] || { echo "stereo_table.sh: dataset folder not found: $data" >&2; exit 2; }
[ -x "$bin" ] || { echo "stereo_table.sh: executable not found: $bin (run scripts/build.sh)" >&2; exit 2; }
mkdir -p "$out"
global=(--log-level warn)
[ -n "${THREADS:-}" ] && global+=(--threads "$THREADS")
frames=()
[ -n "${FRAMES:-}" ] && frames=(--frames "$FRAMES")

for n in $particles; do
  for s in $seeds; do
    dir="$out/n$n/seed$s"
    mkdir -p "$dir"
    if "$bin" "${global[@]}" run "$data" --config "$config" --particles "$n" --seed "$s" --out "$dir" \
        "${frames[@]}" > "$dir/log.txt" 2>&1; then
      echo "N=$n seed=$s done"
    else
      echo "FAILED: N=$n seed=$s (see $dir/log.txt)"
    fi
  done
done

python3 - "$out" <<'PY'
import json, math, os, sys, glob
out = sys.argv[1]
def ms(v, f="{:.4f}"):
    v = [x for x in v if x is not None]
    if not v: return "n/a"
    m = sum(v) / len(v)
    s = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
    return (f + " ± " + f).format(m, s)
def get(m, *keys):
    for k in keys:
        if m is None or k not in m: return None
        m = m[k]
    return m
lines = ["| N | runs | SLAM ATE (m) | VO ATE (m) | SLAM drift % | VO drift % | SLAM t_rel % | VO t_rel % "
         "| SLAM r_rel deg/100m | VO r_rel deg/100m | fps | ESS % | resampling % |",
         "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for d in sorted(glob.glob(os.path.join(out, "n*")), key=lambda p: int(os.path.basename(p)[1:])):
    runs = [json.load(open(f)) for f in sorted(glob.glob(os.path.join(d, "seed*", "metrics.json")))]
    if not runs: continue
    col = lambda *k: [get(m, *k) for m in runs]
    lines.append("| " + " | ".join([
        os.path.basename(d)[1:], str(len(runs)),
        ms(col("slam", "ate", "se3_rmse_m")), ms(col("vo", "ate", "se3_rmse_m")),
        ms(col("slam", "end_point_drift_percent"), "{:.3f}"), ms(col("vo", "end_point_drift_percent"), "{:.3f}"),
        ms(col("slam", "kitti", "t_rel_percent"), "{:.3f}"), ms(col("vo", "kitti", "t_rel_percent"), "{:.3f}"),
        ms(col("slam", "kitti", "r_rel_deg_per_100m"), "{:.3f}"),
        ms(col("vo", "kitti", "r_rel_deg_per_100m"), "{:.3f}"),
        ms(col("timing", "fps"), "{:.1f}"), ms(col("filter", "ess_percent"), "{:.1f}"),
        ms(col("filter", "resampling_percent"), "{:.1f}")]) + " |")
text = "\n".join(lines) + "\n"
open(os.path.join(out, "table.md"), "w").write(text)
print(text)
PY

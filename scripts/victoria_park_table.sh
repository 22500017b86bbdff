#!/usr/bin/env bash
# Victoria Park table in the layout of paper 003 Table III: for every algorithm and particle count, the mean ± std
# over seeds of the position RMSE against GPS, the time per step, the resampling and ESS percentages and the total
# run time, from `glmbslam run` (one run per seed, each writing metrics.json).
#
# Usage: scripts/victoria_park_table.sh [DATA_DIR] [OUT_DIR]
#   DATA_DIR   the Victoria Park folder (default ../shared/data/victoria_park)
#   OUT_DIR    where runs and table.md go (default out/victoria_park_table)
# Environment:
#   GLMBSLAM     the executable (default build/src/app/glmbslam)
#   ALGORITHMS   default "glmb2 glmb-mh phd3 phd1 glmb1 deadreckoning"
#   PARTICLES    default "1 5 10"
#   SEEDS        default "0 1 2 3 4 5 6 7 8 9"
#   CONFIG       config file (default config/victoria_park.yaml)
#   FRAMES       optional step limit (e.g. 1000) for a quick look; empty = the whole dataset
#   JOBS         runs in parallel (default 1; timings are single-core per run, so keep 1 for timing figures)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
data="${1:-$root/../shared/data/victoria_park}"
out="${2:-$root/out/victoria_park_table}"
bin="${GLMBSLAM:-$root/build/src/app/glmbslam}"
algorithms="${ALGORITHMS:-glmb2 glmb-mh phd3 phd1 glmb1 deadreckoning}"
particles="${PARTICLES:-1 5 10}"
seeds="${SEEDS:-0 1 2 3 4 5 6 7 8 9}"
config="${CONFIG:-$root/config/victoria_park.yaml}"
jobs="${JOBS:-1}"
mkdir -p "$out"

runs=()
for a in $algorithms; do
  for n in $particles; do
    [ "$a" = deadreckoning ] && [ "$n" != "$(echo $particles | awk '{print $1}')" ] && continue
    for s in $seeds; do
      runs+=("$a $n $s")
    done
  done
done

run_one() {
  set -euo pipefail
  local a="$1" n="$2" s="$3"
  local dir="$out/$a/n$n/seed$s"
  mkdir -p "$dir"
  local frames=()
  [ -n "${FRAMES:-}" ] && frames=(--frames "0:$FRAMES")
  "$bin" run "$data" --config "$config" --algorithm "$a" --particles "$n" --seed "$s" --out "$dir" "${frames[@]}" \
    > "$dir/log.txt" 2>&1 || { echo "FAILED: $a N=$n seed=$s (see $dir/log.txt)"; return 0; }
  tail -n 1 "$dir/log.txt"
}
export -f run_one
export out bin data config FRAMES

printf '%s\n' "${runs[@]}" | xargs -P "$jobs" -L 1 bash -c 'run_one $0 $1 $2'

python3 - "$out" $algorithms <<'PY'
import json, math, os, sys, glob
out, algos = sys.argv[1], sys.argv[2:]
def ms(v):
    if not v: return "n/a"
    m = sum(v) / len(v)
    s = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
    return f"{m:.2f} ± {s:.2f}"
lines = ["| algorithm | N | runs | position RMSE (m) | ms per step | resampling % | ESS % | total s | landmarks |",
         "|---|---|---|---|---|---|---|---|---|"]
for a in algos:
    for d in sorted(glob.glob(os.path.join(out, a, "n*")), key=lambda p: int(os.path.basename(p)[1:])):
        ms_ = [json.load(open(f)) for f in sorted(glob.glob(os.path.join(d, "seed*", "metrics.json")))]
        if not ms_: continue
        pos = [m["position_rmse_m"] for m in ms_ if m["position_rmse_m"] is not None]
        lines.append(f"| {a} | {os.path.basename(d)[1:]} | {len(ms_)} | {ms(pos)} | "
                     f"{ms([m['ms_per_step']['mean'] for m in ms_])} | {ms([m['resampling_percent'] for m in ms_])} | "
                     f"{ms([m['ess_percent'] for m in ms_])} | {ms([m['total_s'] for m in ms_])} | "
                     f"{ms([m['map']['landmarks'] for m in ms_])} |")
text = "\n".join(lines) + "\n"
open(os.path.join(out, "table.md"), "w").write(text)
print(text)
PY

#!/usr/bin/env bash
# Reproduces the comparison of paper 000 (δ-GLMB-SLAM 2.0, Sensors 2019, Sec. 4.1): δ-GLMB-SLAM 2.0 (glmb2) vs
# δ-GLMB-SLAM 1.0 (glmb1) vs LMB-SLAM (lmb) vs RB-PHD-SLAM 1.0 (phd1) on the paper2019 scenario at the paper's
# clutter rates 1, 5, 10, 15, 15 Monte Carlo runs, 10 particles. Writes one folder per (algorithm, λ) with
# metrics.json and plots, then (scripts/paper2019_figures.py) per clutter rate the figures over time with one
# line per algorithm — RMS position and heading error, mean map OSPA and GOSPA, estimated cardinality against
# the true one — as SVG, and comparison.md, the table of means (position / heading RMSE, mean OSPA and GOSPA,
# mean cardinality error, time per step).
#
# Usage: scripts/paper2019_comparison.sh [OUT_DIR]   (default results/paper2019)
# Environment: GLMBSLAM_BIN (default build/src/app/glmbslam), RUNS (15), PARTICLES (10), SEED (0),
#              ALGORITHMS ("glmb2 glmb1 lmb phd1"; also lmb1, fastslam2, fastslam2-known, glmb_mh, phd3),
#              CLUTTER ("1 5 10 15"), CONFIG (optional YAML for --config), SKIP_RUNS (1: only redraw the figures).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${GLMBSLAM_BIN:-$root/build/src/app/glmbslam}"
out="${1:-$root/results/paper2019}"
runs="${RUNS:-15}"
particles="${PARTICLES:-10}"
seed="${SEED:-0}"
algorithms="${ALGORITHMS:-glmb2 glmb1 lmb phd1}"
clutter_rates="${CLUTTER:-1 5 10 15}"
config_args=()
if [[ -n "${CONFIG:-}" ]]; then config_args=(--config "$CONFIG"); fi
[[ -x "$bin" ]] || { echo "glmbslam binary not found at $bin (build first or set GLMBSLAM_BIN)" >&2; exit 2; }
command -v python3 > /dev/null || { echo "python3 is required for the figures and the table" >&2; exit 2; }
mkdir -p "$out"

for lambda in $clutter_rates; do
  for alg in $algorithms; do
    [[ "${SKIP_RUNS:-0}" == 1 ]] && continue
    dir="$out/${alg}_clutter${lambda}"
    "$bin" --log-level warn sim --scenario paper2019 --algorithm "$alg" --particles "$particles" --runs "$runs" \
      --clutter "$lambda" --seed "$seed" --out "$dir" "${config_args[@]}"
  done
done

python3 "$root/scripts/paper2019_figures.py" "$out" "$algorithms" "$clutter_rates"

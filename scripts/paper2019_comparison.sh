#!/usr/bin/env bash
# Reproduces the comparison of paper 000 (δ-GLMB-SLAM 2.0, Sensors 2019, Sec. 4.1): δ-GLMB-SLAM 2.0 (glmb2) vs
# δ-GLMB-SLAM 1.0 (glmb1) vs RB-PHD-SLAM 1.0 (phd1) on the paper2019 scenario at clutter rates 1, 5, 10, 15,
# 15 Monte Carlo runs, 10 particles; writes one folder per (algorithm, λ) with metrics.json and plots, and one
# table (markdown) of position / heading RMSE, mean OSPA and time per step.
#
# Usage: scripts/paper2019_comparison.sh [OUT_DIR]   (default results/paper2019)
# Environment: GLMBSLAM_BIN (default build/src/app/glmbslam), RUNS (15), PARTICLES (10), SEED (0),
#              ALGORITHMS ("glmb2 glmb1 phd1"), CLUTTER ("1 5 10 15"), CONFIG (optional YAML for --config).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${GLMBSLAM_BIN:-$root/build/src/app/glmbslam}"
out="${1:-$root/results/paper2019}"
runs="${RUNS:-15}"
particles="${PARTICLES:-10}"
seed="${SEED:-0}"
algorithms="${ALGORITHMS:-glmb2 glmb1 phd1}"
clutter_rates="${CLUTTER:-1 5 10 15}"
config_args=()
if [[ -n "${CONFIG:-}" ]]; then config_args=(--config "$CONFIG"); fi
[[ -x "$bin" ]] || { echo "glmbslam binary not found at $bin (build first or set GLMBSLAM_BIN)" >&2; exit 2; }
command -v jq > /dev/null || { echo "jq is required for the table" >&2; exit 2; }
mkdir -p "$out"

for lambda in $clutter_rates; do
  for alg in $algorithms; do
    dir="$out/${alg}_clutter${lambda}"
    "$bin" --log-level warn sim --scenario paper2019 --algorithm "$alg" --particles "$particles" --runs "$runs" \
      --clutter "$lambda" --seed "$seed" --out "$dir" "${config_args[@]}"
  done
done

table="$out/comparison.md"
{
  echo "# paper2019 comparison: $runs runs, $particles particles (seed $seed)"
  echo
  echo "| λ_c | algorithm | position RMSE (m) | heading RMSE (deg) | mean OSPA (m) | final OSPA (m) | ms/step | ESS % |"
  echo "|---|---|---|---|---|---|---|---|"
  for lambda in $clutter_rates; do
    for alg in $algorithms; do
      jq -r --arg l "$lambda" --arg a "$alg" \
        '"| \($l) | \($a) | \(.position_rmse_m*1000|round/1000) | \(.heading_rmse_deg*1000|round/1000) | \(.ospa.mean_over_steps_m*1000|round/1000) | \(.ospa.final_m.mean*1000|round/1000) ± \(.ospa.final_m.std*1000|round/1000) | \(.ms_per_step.mean*1000|round/1000) ± \(.ms_per_step.std*1000|round/1000) | \(.ess_percent*10|round/10) |"' \
        "$out/${alg}_clutter${lambda}/metrics.json"
    done
  done
} > "$table"
cat "$table"

#!/usr/bin/env bash
# Runs the experiment workflow (workflow/Snakefile): the results matrix of a preset of workflow/config.yaml, on
# this machine or through Slurm, then prints where the tables and plots are.
#
# Usage: scripts/experiments.sh [--preset NAME] [--out DIR] [--slurm] [--cores N] [--results-doc] [SNAKEMAKE ARGS...]
#   --preset NAME   smoke (default; minutes on 2 cores), paper (the README figures) or full
#   --out DIR       output root (default: `out` of workflow/config.yaml, out/workflow); results in DIR/NAME/
#   --slurm         submit every job with sbatch (workflow/profiles/slurm); otherwise run locally
#   --cores N       local cores (default: all)
#   --results-doc   afterwards write docs/results.md and the README results block from the aggregate
#   SNAKEMAKE ARGS  passed on, e.g. -n (dry run), --forcerun run, --keep-going
# Environment: GLMBSLAM (executable, default build/src/app/glmbslam; built when absent), GLMBSLAM_DATA (data root).
set -euo pipefail
# Debian's python3 (python3-yaml, python3-matplotlib), not another python3 that may come first on PATH.
py=/usr/bin/python3
[ -x "$py" ] || py=python3
export USER="${USER:-$(id -un)}"  # Snakemake 7's Slurm executor reads $USER (unset in some CI shells)
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
preset=smoke
slurm=0
cores="$(nproc)"
results_doc=0
out=""
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --preset) [ $# -ge 2 ] || { echo "experiments.sh: --preset needs a name" >&2; exit 2; }; preset="$2"; shift 2 ;;
    --out) [ $# -ge 2 ] || { echo "experiments.sh: --out needs a folder" >&2; exit 2; }; out="$2"; shift 2 ;;
    --slurm) slurm=1; shift ;;
    --cores) [ $# -ge 2 ] || { echo "experiments.sh: --cores needs a number" >&2; exit 2; }; cores="$2"; shift 2 ;;
    --results-doc) results_doc=1; shift ;;
    -h|--help) sed -n '2,13p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) extra+=("$1"); shift ;;
  esac
done
command -v snakemake > /dev/null || {
  echo "experiments.sh: snakemake not found (scripts/install_deps.sh --test installs it)" >&2; exit 2; }
bin="${GLMBSLAM:-$root/build/src/app/glmbslam}"
if [ ! -x "$bin" ]; then
  echo "== building glmbslam (scripts/build.sh --target glmbslam)"
  "$root/scripts/build.sh" --target glmbslam
fi
cd "$root"
[ -n "$out" ] || out="$("$py" -c 'import sys, yaml; print(yaml.safe_load(open(sys.argv[1]))["out"])' workflow/config.yaml)"
config=(--config "preset=$preset" "glmbslam=$bin" "out=$out")
if [ "$slurm" = 1 ]; then
  mode=(--profile workflow/profiles/slurm)
else
  mode=(--cores "$cores")
fi
start=$(date +%s)
snakemake --snakefile workflow/Snakefile "${mode[@]}" "${config[@]}" "${extra[@]}"
end=$(date +%s)
if [ "$results_doc" = 1 ]; then
  snakemake --snakefile workflow/Snakefile --cores 1 --forcerun results_doc results_doc "${config[@]}"
fi
echo "== preset $preset done in $((end - start)) s: $out/$preset/{results.csv,summary.md,summary.html,plots/}"

#!/usr/bin/env bash
# CI stage of the experiment workflow (workflow/): runs the smoke preset end to end locally and through a
# single-node Slurm cluster started on this machine, and checks the results.
#
#  1. local: `snakemake --cores 2 --config preset=smoke` into a fresh folder; every run succeeded, one CSV row per
#     run with its metrics and provenance, tables and plots written (workflow/scripts/check_outputs.py); wall time.
#  2. a second invocation has nothing to do (dry run says "Nothing to be done").
#  3. changing one config value (the frame range of one dataset) re-runs only that dataset's jobs and the
#     aggregation (dry run with a modified copy of the config).
#  4. Slurm: munged + slurmctld + slurmd on localhost, configured in a temporary folder
#     (workflow/scripts/local_slurm.sh), the smoke preset through workflow/profiles/slurm; every job went through
#     sbatch (Snakemake's submissions = the cluster's job-completion records, all COMPLETED; every run's
#     provenance has its Slurm job id); the results equal the local run's (compare_results.py: every metric but
#     time and memory). When Slurm cannot run here (not root, packages missing, a daemon does not start), the
#     stage says exactly why and fails, unless WORKFLOW_CI_SLURM=skip, when it says what it checked instead.
#
# Usage: scripts/ci_workflow.sh              (as root on Debian 12; installs its packages with install_deps --test)
# Environment: GLMBSLAM (executable; default build/src/app/glmbslam, built when absent), GLMBSLAM_DATA (data root),
#              WORKFLOW_CI_DIR (work folder; default a new temporary folder, removed on success),
#              WORKFLOW_CI_SLURM (run | skip; default run), CORES (default 2)
set -euo pipefail
# Debian's python3 (python3-yaml, python3-matplotlib), not another python3 that may come first on PATH.
py=/usr/bin/python3
[ -x "$py" ] || py=python3
export USER="${USER:-$(id -un)}"  # Snakemake 7's Slurm executor reads $USER (unset in some CI shells)
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
cores="${CORES:-2}"
stage_start=$(date +%s)
say() { echo "== ci_workflow: $*"; }

bash scripts/install_deps.sh --test
work="${WORKFLOW_CI_DIR:-$(mktemp -d /tmp/glmbslam_workflow_ci.XXXXXX)}"
mkdir -p "$work"
bin="${GLMBSLAM:-$root/build/src/app/glmbslam}"
if [ ! -x "$bin" ]; then
  say "building glmbslam (log $work/build.log)"
  scripts/build.sh --target glmbslam > "$work/build.log" 2>&1 || { tail -30 "$work/build.log"; exit 1; }
fi
say "snakemake $(snakemake --version), slurm-client $(dpkg-query -W -f '${Version}' slurm-client 2>/dev/null || echo absent), $(nproc) cores"
slurm_dir="$work/slurm_cluster"
cleanup() { [ -f "$slurm_dir/slurm.conf" ] && workflow/scripts/local_slurm.sh stop "$slurm_dir" || true; }
trap cleanup EXIT
common=(--snakefile workflow/Snakefile --config preset=smoke "glmbslam=$bin")
failures=0

# 1. local smoke run.
say "1/4 smoke preset locally (--cores $cores) into $work/local"
t0=$(date +%s)
snakemake "${common[@]}" "out=$work/local" --cores "$cores" --printshellcmds > "$work/local.log" 2>&1 || {
  tail -40 "$work/local.log"; say "FAILED: local smoke run (log $work/local.log)"; exit 1; }
t1=$(date +%s)
local_s=$((t1 - t0))
say "local smoke run: $local_s s wall"
"$py" workflow/scripts/check_outputs.py "$work/local/smoke" || failures=$((failures + 1))

# 2. nothing to do the second time.
say "2/4 re-running the finished workflow (dry run)"
snakemake "${common[@]}" "out=$work/local" --cores "$cores" -n > "$work/rerun.log" 2>&1
cat "$work/rerun.log"
if grep -q "Nothing to be done" "$work/rerun.log"; then
  say "re-run: nothing to be done (OK)"
else
  say "FAILED: the finished workflow would run jobs again"; failures=$((failures + 1))
fi
for preset in paper full; do
  if snakemake --snakefile workflow/Snakefile --config "preset=$preset" "glmbslam=$bin" "out=$work/dry" -n \
      > "$work/dry_$preset.log" 2>&1; then
    say "preset $preset resolves: $(grep -A9 '^Job stats' "$work/dry_$preset.log" | awk '$1 == "total" {print $2}' | head -1) jobs (dry run)"
  else
    tail -5 "$work/dry_$preset.log"; say "FAILED: preset $preset does not resolve"; failures=$((failures + 1))
  fi
done

# 3. one changed value re-runs only what depends on it.
say "3/4 changing datasets.r07_clip frames 0:160 -> 0:150 (dry run)"
"$py" - "$work/changed.yaml" <<'PY'
import sys, yaml
c = yaml.safe_load(open("workflow/config.yaml"))
c["datasets"]["r07_clip"]["render"]["frames"] = "0:150"
yaml.safe_dump(c, open(sys.argv[1], "w"))
PY
snakemake "${common[@]}" "out=$work/local" --configfile workflow/config.yaml "$work/changed.yaml" --cores "$cores" \
  -n > "$work/changed.log" 2>&1
"$py" - "$work/changed.log" <<'PY' || failures=$((failures + 1))
import re, sys
text = open(sys.argv[1]).read()
rules, datasets = {}, set()
for block in re.split(r"\n(?=(?:local)?rule \w+:)", text):
    m = re.match(r"(?:local)?rule (\w+):", block)
    if not m:
        continue
    rules[m.group(1)] = rules.get(m.group(1), 0) + 1
    w = re.search(r"wildcards: dataset=([^,\n]+)", block)
    if w:
        datasets.add(w.group(1))
print("jobs to run:", rules, "datasets touched:", sorted(datasets))
ok = (datasets == {"r07_clip"} and rules.get("render") == 1 and rules.get("run") == 5 and
      rules.get("aggregate") == 1 and rules.get("plots") == 1 and set(rules) <= {"render", "run", "aggregate",
                                                                              "plots", "all"})
print("changed config: only r07_clip's render, its 4 SLAM runs and 1 VO run, and the aggregation re-run:",
      "OK" if ok else "FAILED")
sys.exit(0 if ok else 1)
PY

# 4. the same preset through a single-node Slurm cluster.
say "4/4 smoke preset through Slurm (workflow/profiles/slurm) on a single-node cluster on this machine"
slurm_mode="${WORKFLOW_CI_SLURM:-run}"
why=""
if [ "$(id -u)" -ne 0 ]; then why="not root: slurmd must run as root to start jobs as their user";
elif ! command -v slurmctld > /dev/null || ! command -v slurmd > /dev/null || ! command -v munged > /dev/null; then
  why="slurmctld, slurmd or munged not installed (packages slurmctld slurmd slurm-client munge)"
elif ! workflow/scripts/local_slurm.sh start "$slurm_dir" > "$work/slurm_start.log" 2>&1; then
  why="the single-node cluster did not start: $(tail -3 "$work/slurm_start.log" | tr '\n' ' ')"
fi
if [ -n "$why" ]; then
  say "Slurm part NOT RUN: $why"
  snakemake "${common[@]}" "out=$work/slurm" --profile workflow/profiles/slurm -n > "$work/slurm_dry.log" 2>&1 &&
    say "checked instead: the Slurm profile loads and resolves the same $(grep -c '^rule run:' "$work/slurm_dry.log") run jobs (dry run); no job was submitted"
  if [ "$slurm_mode" != skip ]; then failures=$((failures + 1)); fi
else
  export SLURM_CONF="$slurm_dir/slurm.conf"
  say "cluster up: $(sinfo -h -o '%P %D nodes, %c CPUs, %m MB, %t' | head -1) (SLURM_CONF=$SLURM_CONF)"
  t0=$(date +%s)
  snakemake "${common[@]}" "out=$work/slurm" --profile workflow/profiles/slurm --max-status-checks-per-second 1 \
    > "$work/slurm.log" 2>&1 || { tail -40 "$work/slurm.log"; say "FAILED: Slurm smoke run (log $work/slurm.log)";
                                  failures=$((failures + 1)); }
  t1=$(date +%s)
  slurm_s=$((t1 - t0))
  say "Slurm smoke run: $slurm_s s wall"
  submitted=$(grep -o "submitted with SLURM jobid [0-9]*" "$work/slurm.log" | awk '{print $5}' | sort -n)
  n_sub=$(echo "$submitted" | grep -c . || true)
  completed=$(grep -o "JobId=[0-9]* .*JobState=COMPLETED" "$slurm_dir/jobcomp.log" 2>/dev/null |
              sed 's/JobId=\([0-9]*\) .*/\1/' | sort -n || true)
  n_done=$(echo "$completed" | grep -c . || true)
  n_other=$(grep -vc "JobState=COMPLETED" "$slurm_dir/jobcomp.log" 2>/dev/null || true)
  say "sbatch submissions by Snakemake: $n_sub; jobs COMPLETED in the cluster's job-completion log: $n_done; other states: ${n_other:-0}"
  if [ "$n_sub" -gt 0 ] && [ "$submitted" = "$completed" ] && [ "${n_other:-0}" = 0 ]; then
    say "every job went through sbatch and completed (OK)"
  else
    say "FAILED: submissions and completed Slurm jobs differ"; failures=$((failures + 1))
  fi
  "$py" workflow/scripts/check_outputs.py "$work/slurm/smoke" --slurm || failures=$((failures + 1))
  "$py" workflow/scripts/compare_results.py "$work/local/smoke/results.csv" "$work/slurm/smoke/results.csv" ||
    failures=$((failures + 1))
fi

say "stage wall time $(($(date +%s) - stage_start)) s (local smoke ${local_s} s, Slurm smoke ${slurm_s:-n/a} s)"
if [ "$failures" -ne 0 ]; then
  say "FAILED: $failures check(s); outputs kept in $work"
  exit 1
fi
[ -z "${WORKFLOW_CI_DIR:-}" ] && rm -rf "$work"
say "OK"

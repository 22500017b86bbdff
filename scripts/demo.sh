#!/usr/bin/env bash
# The README main command: installs the dependencies, builds, renders the built-in synthetic stereo sequence
# (a ~400 m drive that returns to its start, exact ground truth) and runs δ-GLMB-SLAM 2.0 on it, then prints
# where the trajectory, map and report are.
# Usage: scripts/demo.sh [output folder, default out/demo]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" -DGLMBSLAM_BUILD_TESTS=OFF -DGLMBSLAM_BUILD_BENCH=OFF > "${TMPDIR:-/tmp}/glmbslam_build.log" 2>&1 || { tail -50 "${TMPDIR:-/tmp}/glmbslam_build.log"; exit 1; }
build="${GLMBSLAM_BUILD_DIR:-$root/build}"
glmbslam="$build/src/app/glmbslam"
out="${1:-$root/out/demo}"
mkdir -p "$out"
if [ ! -f "$out/synthetic/poses/00.txt" ]; then
  echo "== rendering the built-in synthetic stereo sequence into $out/synthetic"
  "$glmbslam" render --out "$out/synthetic"
fi
echo "== running δ-GLMB-SLAM 2.0 on it"
"$glmbslam" run "$out/synthetic/sequences/00" --config "$root/config/kitti00-02.yaml" --out "$out/run"
echo
echo "Trajectory: $out/run/trajectory.txt   Map: $out/run/map.pcd   Report: $out/run/metrics.json   Plots: $out/run/plots/"

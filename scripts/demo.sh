#!/usr/bin/env bash
# The README main command: installs the build dependencies, builds the glmbslam executable alone (tests and
# benchmarks are scripts/test.sh's), renders the built-in synthetic stereo sequence (a ~460 m drive that
# returns to its start, exact ground truth), runs δ-GLMB-SLAM 2.0 on it and prints where the interactive
# report, the trajectory and the map are.
# Usage: scripts/demo.sh [output folder, default out/demo]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GLMBSLAM_BUILD_DIR:-$root/build}"
out="${1:-$root/out/demo}"
log="${TMPDIR:-/tmp}/glmbslam_build.log"
"$root/scripts/install_deps.sh"
echo "== building glmbslam into $build (log: $log)"
"$root/scripts/build.sh" --target glmbslam -DGLMBSLAM_BUILD_TESTS=OFF -DGLMBSLAM_BUILD_BENCH=OFF > "$log" 2>&1 ||
  { tail -50 "$log"; exit 1; }
glmbslam="$build/src/app/glmbslam"
mkdir -p "$out"
if [ ! -f "$out/synthetic/poses/00.txt" ]; then
  echo "== rendering the built-in synthetic stereo sequence into $out/synthetic"
  "$glmbslam" render --out "$out/synthetic"
fi
echo "== running δ-GLMB-SLAM 2.0 on it"
"$glmbslam" run "$out/synthetic/sequences/00" --config "$root/config/kitti00-02.yaml" --out "$out/run"
echo
echo "Report (open in a browser): $out/run/report.html"
echo "Trajectory: $out/run/trajectory.txt   Map: $out/run/map.pcd   Metrics: $out/run/metrics.json   Plots: $out/run/plots/"

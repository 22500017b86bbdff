#!/usr/bin/env bash
# The README main command: installs the build dependencies, builds the glmbslam executable alone (tests and
# benchmarks are scripts/test.sh's), renders the built-in synthetic stereo sequence (a ~460 m drive that
# returns to its start, exact ground truth), runs δ-GLMB-SLAM 2.0 with the RFS-ML refinement on it (sliding
# windows online, then loop closing and one maximum-likelihood pass over the whole run) and prints where the
# interactive report, the trajectories and the maps are.
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
echo "== running δ-GLMB-SLAM 2.0 with the RFS-ML refinement on it"
"$glmbslam" run "$out/synthetic/sequences/00" --config "$root/config/kitti00-02.yaml" --refine ml --out "$out/run"
echo
echo "Report (open in a browser): $out/run/report.html"
echo "Refined: $out/run/trajectory_refined.txt, $out/run/map_refined.pcd   Filter: $out/run/trajectory.txt, $out/run/map.pcd"
echo "Metrics: $out/run/metrics.json   Plots: $out/run/plots/"

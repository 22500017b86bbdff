#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with clang (build-fuzz/, -DGLMBSLAM_BUILD_FUZZERS=ON: ASan + UBSan +
# coverage instrumentation) and runs each for a bounded time on its seed corpus (fuzz/corpus/<target>/, small
# hand-cut samples of the shared data). Prints one line per target: executions, coverage (edges) and features
# reached. Fails on any crash, hang (> 10 s per input; 60 s for mat), out-of-memory or sanitizer report; the input that caused
# it is kept in build-fuzz/artifacts/ (turn it into a regression test in tests/io or the matching folder).
#
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]     (default 25 s, every target)
# Environment: GLMBSLAM_FUZZ_BUILD_DIR (default build-fuzz), JOBS (build parallelism; default nproc),
#              FUZZ_RUNS=N: instead of a time budget, N executions per target from a fixed seed (-seed=1) and
#              the seed corpus alone: the same inputs on every machine, so a CI run is reproducible (.ci/run)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GLMBSLAM_FUZZ_BUILD_DIR:-$root/build-fuzz}"
seconds="${1:-25}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(kitti_calib kitti_times kitti_poses kitti_raw_calib oxts tum_trajectory euroc image mat config)
fi
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang-14 \
  -DCMAKE_CXX_COMPILER=clang++-14 -DGLMBSLAM_BUILD_FUZZERS=ON -DGLMBSLAM_BUILD_TESTS=OFF \
  -DGLMBSLAM_BUILD_BENCH=OFF -DGLMBSLAM_WERROR=OFF >/dev/null
cmake --build "$build" --target fuzzers -j "${JOBS:-$(nproc)}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
printf '%-16s %12s %8s %8s %s\n' target executions cov ft result
for t in "${targets[@]}"; do
  work="$build/corpus/$t"
  artifacts="$build/artifacts"
  budget=(-max_total_time="$seconds")
  if [ -n "${FUZZ_RUNS:-}" ]; then
    rm -rf "$work"  # only the seed corpus: the same inputs wherever it runs
    budget=(-runs="$FUZZ_RUNS" -seed=1)
  fi
  # a 64 KiB .mat input may hold a compressed variable that inflates a thousandfold (zlib's ratio, accepted by
  # the reader): ~67 MB decoded twice under ASan takes seconds, a slow input rather than a hang
  timeout=10
  [ "$t" = mat ] && timeout=60
  mkdir -p "$work" "$artifacts"
  log="$build/fuzz_$t.log"
  result=ok
  if ! "$build/fuzz/fuzz_$t" "$work" "$root/fuzz/corpus/$t" "${budget[@]}" -timeout="$timeout" \
    -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 -artifact_prefix="$artifacts/$t-" >"$log" 2>&1; then
    result="FAILED (see $log)"
    status=1
    # the report itself, so a CI log shows the cause without the build folder
    sed -n '/ERROR: \|SUMMARY: \|runtime error: \|terminate called/,$p' "$log" | grep -v '^HDF5-DIAG\|^  *#0[0-9][0-9] in H5\|^    m[ai][jn]or:' | head -60 >&2
  fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -1 | cut -d' ' -f2)
  printf '%-16s %12s %8s %8s %s\n' "$t" "${execs:-?}" "${cov:-?}" "${ft:-?}" "$result"
done
exit $status

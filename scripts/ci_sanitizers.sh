#!/usr/bin/env bash
# CI stage: AddressSanitizer + UndefinedBehaviorSanitizer build of the application and the whole test suite, in
# its own build folder, then ctest on it. Any ASan or UBSan report fails the stage (UBSan errors are fatal:
# -fno-sanitize-recover=all; ASan aborts on its first error).
#
# Usage: scripts/ci_sanitizers.sh [ctest args...]   e.g. scripts/ci_sanitizers.sh -L smoke
# Environment: GLMBSLAM_ASAN_BUILD_DIR (default build-asan), JOBS (default: nproc)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GLMBSLAM_ASAN_BUILD_DIR:-$root/build-asan}"
jobs="${JOBS:-$(nproc)}"
# EIGEN_MALLOC_ALREADY_ALIGNED=1: under -fsanitize=address Eigen switches to its own aligned malloc/free, while
# Debian's uninstrumented libraries (Ceres, PCL) keep plain malloc/free for the Eigen objects they hand over
# (ceres::GradientChecker::ProbeResults): freed here, that mismatch is a false heap-buffer-overflow. ASan's
# malloc is 16-byte aligned on x86-64, as glibc's, so the plain path is valid.
flags="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -DEIGEN_MALLOC_ALREADY_ALIGNED=1"
# -O1 with line tables only: the usual sanitizer setting (stack traces with file:line), and a much faster
# compile than -O2 with full debug info.
opt="-O1 -g1 -DNDEBUG"
start=$(date +%s)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGLMBSLAM_BUILD_TESTS=ON \
  -DGLMBSLAM_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$opt" -DCMAKE_C_FLAGS_RELWITHDEBINFO="$opt" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build" -j "$jobs"
built=$(date +%s)
# Leaks are reported too (LeakSanitizer).
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
ctest --output-on-failure -j "$jobs" "$@"
end=$(date +%s)
echo "ci_sanitizers: build $((built - start)) s, tests $((end - built)) s"

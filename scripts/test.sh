#!/usr/bin/env bash
# The README test command: installs the dependencies, builds, and runs the whole test suite with ctest.
# Tests that need ../shared/data (or $GLMBSLAM_DATA) skip with a message when it is absent.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install_deps.sh" --test
"$root/scripts/build.sh" -DGLMBSLAM_BUILD_TESTS=ON -DGLMBSLAM_BUILD_BENCH=ON
build="${GLMBSLAM_BUILD_DIR:-$root/build}"
cd "$build"
ctest --output-on-failure -j "$(nproc)"

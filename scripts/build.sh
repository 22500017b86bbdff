#!/usr/bin/env bash
# Configures and builds glmbslam (Release) into build/ (GLMBSLAM_BUILD_DIR overrides) using all cores.
# Usage: scripts/build.sh [--target NAME]... [extra cmake configure args]
#   --target NAME  build only this target (repeatable; e.g. --target glmbslam); default: everything
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GLMBSLAM_BUILD_DIR:-$root/build}"
targets=()
configure_args=()
while [ $# -gt 0 ]; do
  case "$1" in
    --target)
      [ $# -ge 2 ] || { echo "build.sh: --target needs a target name" >&2; exit 2; }
      targets+=(--target "$2")
      shift 2
      ;;
    *)
      configure_args+=("$1")
      shift
      ;;
  esac
done
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "${configure_args[@]}"
cmake --build "$build" "${targets[@]}" -j "$(nproc)"

#!/usr/bin/env bash
# Installs every Debian package glmbslam needs to build, test and plot. Idempotent.
set -euo pipefail
PKGS=(
  build-essential cmake g++ pkg-config git
  libopencv-dev libeigen3-dev libpcl-dev libceres-dev libyaml-cpp-dev libmatio-dev
  libcli11-dev libspdlog-dev libopenmpi-dev nlohmann-json3-dev libgtest-dev libgmock-dev libbenchmark-dev
)
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PKGS[@]} packages already installed"
  exit 0
fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"

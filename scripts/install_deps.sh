#!/usr/bin/env bash
# Installs the Debian packages glmbslam needs. Idempotent.
# Usage: scripts/install_deps.sh          build and run (what scripts/demo.sh needs)
#        scripts/install_deps.sh --test   also what the test suite needs (scripts/test.sh, .ci/run)
set -euo pipefail
BUILD_PKGS=(
  build-essential cmake g++ pkg-config git
  libopencv-dev libeigen3-dev libpcl-dev libceres-dev libsuitesparse-dev libopenblas-dev libyaml-cpp-dev libmatio-dev
  libcli11-dev libspdlog-dev libopenmpi-dev nlohmann-json3-dev zlib1g-dev
)
# Only for the tests, benchmarks and CI stages (one package a line; keep each with a comment saying what needs it).
TEST_PKGS=(
  libgtest-dev libgmock-dev libbenchmark-dev  # GoogleTest suite, Google Benchmark micro-benchmarks
  chromium  # loads report.html headless in the report test (tests/app/test_report_html_browser.cpp)
  snakemake python3-matplotlib python3-yaml python3-jinja2 slurmctld slurmd slurm-client munge  # experiment workflow and its local/Slurm CI stage (scripts/ci_workflow.sh; jinja2: workflow/scripts/results_doc.py)
  clang-14 libclang-rt-14-dev  # libFuzzer targets of fuzz/ (scripts/fuzz.sh: clang with -fsanitize=fuzzer)
)
PKGS=("${BUILD_PKGS[@]}")
if [ "${1:-}" = "--test" ]; then PKGS+=("${TEST_PKGS[@]}"); fi
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

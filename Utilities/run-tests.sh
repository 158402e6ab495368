#!/usr/bin/env bash
# Install what is missing, build, and run every test (GoogleTest core tests and pvpython
# plugin tests, headless). .ci/run calls exactly this.
#   bash Utilities/run-tests.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BRT_BUILD_DIR:-$root/build}
bash "$root/Utilities/install-deps.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$(nproc)"
cd "$build"
ctest --output-on-failure -j "$(nproc)"

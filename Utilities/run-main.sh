#!/usr/bin/env bash
# The main job: install what is missing, build, and measure a real part from Data/.
#   bash Utilities/run-main.sh [MODEL.step] [OUT_DIR]
# Writes OUT_DIR (default build/out/<model>) with the .vtp, the summary .csv and a PNG.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BRT_BUILD_DIR:-$root/build}
model=${1:-$root/Data/ExpansionCard_SelfTapping.stp}
name=$(basename "${model%.*}")
out=${2:-$build/out/$name}
bash "$root/Utilities/install-deps.sh"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$(nproc)"
bash "$root/Utilities/run-headless.sh" pvpython "$root/Utilities/brepthickness_batch.py" "$model" --out "$out" \
  --plugin "$build/lib/paraview-plugins/BRepThickness/BRepThickness.so"

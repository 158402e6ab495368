#!/usr/bin/env bash
# Installs every Debian 12 package BRepThickness needs to build, test and render headless.
# Idempotent: installs only what is missing. Run as root (or with sudo available).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  # ParaView 5.11 SDK (bundles VTK 9.2). Never libvtk9-dev: it conflicts with python3-paraview.
  paraview paraview-dev python3-paraview libdouble-conversion-dev libglew-dev libopenmpi-dev openmpi-bin
  # OpenCASCADE 7.6
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev libocct-ocaf-dev libocct-visualization-dev libtbb-dev
  # OpenCL: ICD loader, headers, PoCL CPU driver
  ocl-icd-opencl-dev opencl-headers opencl-c-headers opencl-clhpp-headers pocl-opencl-icd clinfo
  # Tests
  libgtest-dev googletest
  # The kernel's GPU code size (Testing/KernelGpuCodeSize.sh): clang, LLVM and libclc's PTX built-ins
  clang-14 llvm-14 libclc-14
  # The midsurface test runs the exported shell deck in CalculiX
  calculix-ccx
  # Headless rendering
  xvfb xauth libgl1-mesa-dri
  # GUI tests: the screenshot of the ParaView window and its comparison with the baseline;
  # Qt's SVG plugins draw ParaView's toolbar icons (the paraview package only recommends them)
  imagemagick libqt5svg5
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"

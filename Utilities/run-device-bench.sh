#!/bin/bash
# The GPU benchmark, prepared to run in one call on a machine lent for a few minutes (issue "One
# solver, certain and fast": samples/s at 1M samples on every Data/ real part, float and double,
# end to end). Two steps, an export here and a run there:
#
#   Utilities/run-device-bench.sh export [BUILD]
#       here (the full build in BUILD, default build/): writes the solve dumps of the four real
#       parts of Data/ to BUILD/device-dumps (36 MB), which the call carries.
#   Utilities/run-device-bench.sh export-dense [BUILD]
#       the same parts with finer display meshes (463k-890k distinct samples each, --max-edge),
#       xz-compressed to BUILD/device-dense (47 MB): a GPU solves copies of a sample faster than
#       distinct samples, so counts above the mesh's overstate it (docs/Solver.md, Benchmark).
#       `run` unpacks *.brtsolve.xz itself; run it with --counts 0 (every sample once).
#   Utilities/run-device-bench.sh run DUMPS OUT [--device D] [--counts N,...] [--build DIR] [--limit S]
#       there: configures and builds the solver-only variant (no OpenCASCADE, no VTK; CMake, a
#       C++17 compiler and an OpenCL library are all it needs) and runs brt_thickness_bench on
#       every DUMPS/*.brtsolve in float, then in double, each against the native device on every
#       core, with each solve's phases (--phases: host and device time). Tables and the build's
#       log go to OUT (gpu-float.txt, gpu-double.txt, build.log, platform.txt). Defaults:
#       --device gpu, --counts 10000,100000,1000000, --limit 240 (seconds for each precision's
#       run).
#
# On an NVIDIA machine whose image has the CUDA toolkit but no OpenCL vendor file, the script
# takes CUDA's OpenCL headers and loader and points the loader at the driver's OpenCL library
# (OCL_ICD_VENDORS / OCL_ICD_FILENAMES). docs/Solver.md, "Benchmark", gives the call.
set -u

usage()
{
  sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
}

root=$(cd "$(dirname "$0")/.." && pwd)
step=${1:-}
[ -n "$step" ] || usage
shift

if [ "$step" = export-dense ]; then
  build=${1:-$root/build}
  bench=$build/Utilities/brt_thickness_bench
  [ -x "$bench" ] || { echo "run-device-bench: no $bench (build the project first)" >&2; exit 1; }
  command -v xz > /dev/null || { echo "run-device-bench: export-dense needs xz (apt-get install xz-utils)" >&2; exit 1; }
  mkdir -p "$build/device-dense" || exit 1
  rm -f "$build"/device-dense/*.brtsolve "$build"/device-dense/*.brtsolve.xz
  # The longest mesh edge per part (mm): about 0.46-0.89 million vertices each, 47 MB in all
  # once compressed, under the device tool's 64 MiB with the working tree.
  for spec in ExpansionCard_SelfTapping.stp:0.168 FRAMEWORK_DESKTOP_BLANK_TILE.stp:0.138 \
    NIST_MBE_PMI_11.stp:0.142 fw13_hinge_l_assy.stp:0.15; do
    "$bench" --device none --no-native --counts 0 --max-edge "${spec#*:}" \
      --export "$build/device-dense" "$root/Data/${spec%%:*}" || exit 1
  done
  xz -T0 -6 "$build"/device-dense/*.brtsolve || exit 1
  du -ch "$build"/device-dense/*.brtsolve.xz
  exit 0
fi

if [ "$step" = export ]; then
  build=${1:-$root/build}
  bench=$build/Utilities/brt_thickness_bench
  [ -x "$bench" ] || { echo "run-device-bench: no $bench (build the project first)" >&2; exit 1; }
  mkdir -p "$build/device-dumps" || exit 1
  "$bench" --device none --no-native --counts 1000 --export "$build/device-dumps" \
    "$root"/Data/ExpansionCard_SelfTapping.stp "$root"/Data/FRAMEWORK_DESKTOP_BLANK_TILE.stp \
    "$root"/Data/NIST_MBE_PMI_11.stp "$root"/Data/fw13_hinge_l_assy.stp || exit 1
  du -ch "$build"/device-dumps/*.brtsolve
  exit 0
fi

[ "$step" = run ] || usage
dumps=${1:-}
out=${2:-}
[ -n "$dumps" ] && [ -n "$out" ] || usage
shift 2
device=gpu
counts=10000,100000,1000000
bdir=/tmp/brt-solver-only
limit=240
while [ $# -gt 0 ]; do
  case "$1" in
    --device) device=$2; shift 2 ;;
    --counts) counts=$2; shift 2 ;;
    --build) bdir=$2; shift 2 ;;
    --limit) limit=$2; shift 2 ;;
    *) usage ;;
  esac
done
mkdir -p "$out" || exit 1
# Compressed dumps (export-dense) are unpacked to /tmp first (xz, else Python's lzma).
if ls "$dumps"/*.brtsolve.xz > /dev/null 2>&1; then
  rm -rf /tmp/brt-dumps && mkdir -p /tmp/brt-dumps || exit 1
  for f in "$dumps"/*.brtsolve.xz; do
    to=/tmp/brt-dumps/$(basename "$f" .xz)
    if command -v xz > /dev/null; then
      xz -dc "$f" > "$to" || exit 1
    else
      python3 -c "import lzma, shutil, sys; shutil.copyfileobj(lzma.open(sys.argv[1]), open(sys.argv[2], 'wb'))" "$f" "$to" || exit 1
    fi
  done
  dumps=/tmp/brt-dumps
fi
ls "$dumps"/*.brtsolve > /dev/null 2>&1 || { echo "run-device-bench: no .brtsolve files in $dumps" >&2; exit 1; }

# The loader finds a vendor through /etc/OpenCL/vendors; where that names none, the NVIDIA
# driver's library directly.
if ! ls /etc/OpenCL/vendors/*.icd > /dev/null 2>&1; then
  nv=$( (ldconfig -p 2> /dev/null | awk '/libnvidia-opencl.so.1/ {print $NF; exit}'
    ls /usr/local/nvidia/lib64/libnvidia-opencl.so.1 /usr/lib/x86_64-linux-gnu/libnvidia-opencl.so.1 2> /dev/null) | head -1)
  if [ -n "$nv" ]; then
    mkdir -p /tmp/brt-icd && echo "$nv" > /tmp/brt-icd/nvidia.icd
    export OCL_ICD_VENDORS=/tmp/brt-icd OCL_ICD_FILENAMES=$nv
  fi
fi
{
  echo "date: $(date -u)"
  echo "host: $(uname -a)"
  echo "cpus: $(nproc)"
  command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv
  echo "OpenCL vendor: ${OCL_ICD_FILENAMES:-/etc/OpenCL/vendors}"
} > "$out/platform.txt" 2>&1

gen=()
command -v ninja > /dev/null && gen=(-G Ninja)
configure()
{
  cmake -S "$root" -B "$bdir" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DBRT_SOLVER_ONLY=ON "$@"
}
# OpenCL: the system's where CMake finds it, else the CUDA toolkit's headers and loader.
extra=()
if ! configure > "$out/build.log" 2>&1; then
  for cuda in /usr/local/cuda /usr/local/cuda-*; do
    lib=$(ls "$cuda"/lib64/libOpenCL.so* "$cuda"/targets/x86_64-linux/lib/libOpenCL.so* 2> /dev/null | head -1)
    if [ -f "$cuda/include/CL/cl.h" ] && [ -n "$lib" ]; then
      extra=(-DOpenCL_INCLUDE_DIR="$cuda/include" -DOpenCL_LIBRARY="$lib")
      break
    fi
  done
  rm -f "$bdir/CMakeCache.txt"
  if [ ${#extra[@]} -eq 0 ] || ! configure "${extra[@]}" >> "$out/build.log" 2>&1; then
    echo "run-device-bench: CMake found no OpenCL (its log: $out/build.log)" >&2
    tail -30 "$out/build.log" >&2
    exit 1
  fi
fi
echo "OpenCL: ${extra[*]:-as CMake found it}" >> "$out/platform.txt"
if ! cmake --build "$bdir" -j "$(nproc)" >> "$out/build.log" 2>&1; then
  echo "run-device-bench: the solver-only build failed (its log: $out/build.log)" >&2
  tail -30 "$out/build.log" >&2
  exit 1
fi
rc=0
for precision in float double; do
  flag=()
  [ $precision = double ] && flag=(--double)
  echo "== $precision, --device $device, counts $counts"
  # Each precision within its own time limit, so that a driver whose compiler stalls on one
  # program (the H200's first call, docs/Solver.md "Compile time on GPUs") still leaves the other.
  timeout "$limit" "$bdir/brt_thickness_bench" --device "$device" "${flag[@]}" --phases --counts "$counts" \
    "$dumps"/*.brtsolve 2>&1 | tee "$out/gpu-$precision.txt"
  status=${PIPESTATUS[0]}
  [ "$status" -eq 124 ] && echo "run-device-bench: $precision stopped after $limit s" | tee -a "$out/gpu-$precision.txt"
  [ "$status" -eq 0 ] || rc=1
done
exit $rc

#!/bin/bash
# The local benchmark table (issue "One solver, certain and fast": samples/s of the native C++
# path and of PoCL on every real part of Data/, at the defaults, at three sample counts and on
# every vertex, with peak host memory), as docs/bench/local-speed.txt keeps it:
#
#   Utilities/run-local-bench.sh [BUILD] > table.txt
#
# BUILD (default build/) holds brt_thickness_bench. Prints a header (machine, date, commit; each
# block names its OpenCL device) and these blocks: native and PoCL float on every vertex, twice; the same at 10000, 31623 and
# 100000 samples; PoCL's double kernels on every vertex and at those counts; the native device on
# one core (taskset -c 0) on every vertex. About a minute on a 2-core machine; run it on a
# quiet machine, since every figure is one timed run. A program that prints figures, not a test.
set -eu -o pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
bench=$build/Utilities/brt_thickness_bench
[ -x "$bench" ] || { echo "error: $bench not built (cmake --build $build)" >&2; exit 2; }
parts=()
for f in "$root"/Data/*.stp; do
  parts+=("$f")
done
cpu=$(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -1)
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)
echo "# brt_thickness_bench on this $(nproc)-core machine ($cpu), $(date -u +%Y-%m-%d), commit $commit; samples/s"
echo "# native = the kernel source compiled as C++ (double, every core); cl = PoCL float (finished on the device) unless marked double; host_MiB = peak RSS of the run so far"
echo "# Utilities/run-local-bench.sh on the real parts of Data/: $(for f in "${parts[@]}"; do basename "$f"; done | tr '\n' ' ')"
block()
{
  echo "# $1"
  shift
  "$bench" "$@" "${parts[@]}" 2>&1 | grep -v -e '^$' -e '^OpenCL: building'
}
block "every vertex, run 1" --device cpu --counts 0
block "every vertex, run 2" --device cpu --counts 0
block "10000,31623,100000" --device cpu --counts 10000,31623,100000
block "double kernels, every vertex" --device cpu --double --counts 0
block "double kernels, 10000,31623,100000" --device cpu --double --counts 10000,31623,100000
if command -v taskset > /dev/null; then
  echo "# one core, native, every vertex"
  taskset -c 0 "$bench" --device none --counts 0 "${parts[@]}" 2>&1 | grep -v '^$'
fi

#!/bin/bash
# Instructions per sample of the solve on the native device, counted by valgrind's callgrind: a
# figure that does not move with the machine's load, for comparing two versions of the kernel
# source where the timings do not settle it (on a shared 2-core VM the same binary's samples/s
# vary by a third from run to run; docs/Solver.md, Benchmark, "Instructions per sample").
#
#   Utilities/count-instructions.sh [--build DIR] FILE.brtsolve|FILE.step ...
#
# Runs BUILD/Utilities/brt_thickness_bench --device none --counts 0 (every mesh vertex, the native
# device) under callgrind, once per file, and prints per file the samples and the instructions per
# sample of the whole solve (solve_sample) and of its steps. The steps are counted inclusively
# (a step's count holds the calls it makes), so they overlap and do not add up to the whole:
# initialise is eq. 1's walks over s1 (the start and the verification), find_point_inside the
# certification (certify_patch and certify_edge its patch and edge searches), solve_from the
# Newtons of eq. 4 and 7 (surface_newton), eval_patch every patch evaluation wherever it is
# called. The preparation (the trees, the packing) is not counted. Instructions are not time: a
# change that walks fewer nodes shows here, one that waits less on memory may not. Installs
# valgrind (Debian's package) where it is missing. About 30 times slower than the solve itself.
# Counts the baseline build of the kernel source (BRT_NATIVE_BASELINE=1): valgrind 3.19 cannot
# decode some of the AVX moves of the x86-64-v3 build (vmovq between registers), and the two
# builds run the same operations in the same order.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
build=$root/build
if [ "${1:-}" = --build ]; then
  build=${2:?--build DIR}
  shift 2
fi
[ $# -gt 0 ] || { sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
bench=$build/Utilities/brt_thickness_bench
[ -x "$bench" ] || { echo "count-instructions: no $bench (build the project first)" >&2; exit 1; }
if ! command -v valgrind > /dev/null || ! command -v callgrind_annotate > /dev/null; then
  apt-get install -y -qq --no-install-recommends valgrind > /dev/null ||
    { echo "count-instructions: valgrind is missing and could not be installed" >&2; exit 1; }
fi
steps="solve_sample initialise find_point_inside certify_patch certify_edge solve_from surface_newton eval_patch exact_finish"
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
printf '%-34s %8s' model samples
for s in $steps; do printf ' %11s' "$s"; done
printf '\n'
rc=0
for file in "$@"; do
  name=$(basename "$file")
  if ! BRT_NATIVE_BASELINE=1 valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$bench" --device none --counts 0 \
    "$file" > "$tmp/out" 2> "$tmp/err"; then
    echo "count-instructions: $file: the bench failed: $(grep -v "^==" "$tmp/err" | tail -1)" >&2
    rc=1
    continue
  fi
  # The bench's table: the samples are its second column.
  samples=$(awk 'NR > 1 && $2 ~ /^[0-9]+$/ { print $2; exit }' "$tmp/out")
  [ -n "$samples" ] && [ "$samples" -gt 0 ] ||
    { echo "count-instructions: $file: no samples in the bench's table: $(grep -v "^==" "$tmp/err" | tail -1)" >&2
      rc=1; continue; }
  callgrind_annotate --inclusive=yes --threshold=100 "$tmp/cg" > "$tmp/annotated" 2> /dev/null
  printf '%-34s %8d' "$name" "$samples"
  for s in $steps; do
    # The kernel source's function (brt::kernel::NAME), the largest count where callgrind lists
    # it more than once.
    ir=$(grep -E "brt::kernel::$s\(" "$tmp/annotated" |
      awk '{ gsub(",", "", $1); if ($1 + 0 > m) m = $1 + 0 } END { printf "%.0f\n", m + 0 }')
    awk -v ir="$ir" -v n="$samples" 'BEGIN { printf " %11.0f", ir / n }'
  done
  printf '\n'
done
exit $rc

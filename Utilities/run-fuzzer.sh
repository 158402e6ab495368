#!/usr/bin/env bash
# Fuzzes the reader core with libFuzzer (clang 14) for a given time and reports what it found.
#   bash Utilities/run-fuzzer.sh [SECONDS] [checked|raw]
# checked (default): the reader as it runs in its worker (text check, then OpenCASCADE);
# raw: OpenCASCADE alone (the reader before the text check), for comparison.
# Seeds: the small models of Data/. Works in build-fuzz/ (corpus, crash files, log); prints the
# executions, the crash files and the distinct crashes (by their three top stack frames).
# A crash that the worker's isolation turns into an error is still a crash here: replay the
# files with build/Testing/brt_step_replay to see what the reader makes of them.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-3600}
mode=${2:-checked}
build=${BRT_FUZZ_BUILD_DIR:-$root/build-fuzz}
bash "$root/Utilities/install-deps.sh"
command -v clang++-14 >/dev/null || apt-get install -y -qq --no-install-recommends clang-14
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRT_FUZZ=ON \
  -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 >/dev/null
cmake --build "$build" --target brt_fuzz_step_reader
work="$build/$mode"
mkdir -p "$work/corpus" "$work/crashes"
for f in plate.step l_bracket.step hole_plate.step tube.step spherical_shell.step \
  toroidal_shell.step NIST_MBE_PMI_11.stp; do
  cp -n "$root/Data/$f" "$work/corpus/" 2>/dev/null || true
done
env=()
[ "$mode" = raw ] && env=(BRT_FUZZ_RAW=1)
cd "$work"
set +e
env "${env[@]}" ASAN_OPTIONS=detect_leaks=0:dedup_token_length=3 \
  "$build/brt_fuzz_step_reader" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
  -timeout=20 -rss_limit_mb=4096 -max_len=200000 -max_total_time="$seconds" \
  -artifact_prefix="$work/crashes/" "$work/corpus" >"$work/fuzz.log" 2>&1
set -e
rm -f "$work"/brt-fuzz-*.step # the inputs of children killed on a crash or a time-out
last=$(grep -E "^#[0-9]+: cov:" "$work/fuzz.log" | tail -1)
echo "mode $mode, $seconds s: $last"
crashes=$(ls "$work/crashes" | grep -c "^crash-" || true)
timeouts=$(ls "$work/crashes" | grep -c "^timeout-" || true)
echo "crash files $crashes, timeout files $timeouts"
# Distinct crashes: replay each crash file once and take ASan's dedup token.
: >"$work/tokens.txt"
for f in "$work"/crashes/crash-*; do
  [ -e "$f" ] || continue
  tok=$( (env "${env[@]}" ASAN_OPTIONS=detect_leaks=0:dedup_token_length=3 timeout 60 \
    "$build/brt_fuzz_step_reader" "$f" 2>&1 || true) | grep -m1 DEDUP_TOKEN | sed 's/DEDUP_TOKEN: //' || true)
  echo "${tok:-no-token} $(basename "$f")" >>"$work/tokens.txt"
done
echo "distinct crashes (three top frames):"
cut -d' ' -f1 "$work/tokens.txt" | sort | uniq -c | sort -rn || true

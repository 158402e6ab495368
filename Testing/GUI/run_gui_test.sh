#!/usr/bin/env bash
# GUI test in the real ParaView client (run under Utilities/run-headless.sh): plays back the user's
# steps (a ParaView Qt test script), waits until the playback reports success, takes a screenshot
# of the screen (ImageMagick's import), crops it to the ParaView window, and compares it with the
# baseline: it fails when more than MAX_SHARE of the pixels differ by more than 10% in colour.
# The status bar (its memory gauge changes from run to run) is cut off.
#   run_gui_test.sh PLUGIN_DIR SCRIPT.xml BASELINE.png WORK_DIR [MAX_SHARE]
set -uo pipefail
plugin_dir=$1 script=$2 baseline=$3 work=$4 max_share=${5:-0.0002}
mkdir -p "$work"
shot="$work/$(basename "$baseline")"
log="$work/paraview.log"
# --dr: no user settings, so the window, its layout and its colours are ParaView's defaults.
PV_PLUGIN_PATH="$plugin_dir" paraview --dr --test-script="$script" --test-directory="$work" >"$log" 2>&1 &
pid=$!
for _ in $(seq 600); do
  grep -q 'is finished' "$log" && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.5
done
if ! grep -q 'is finished. Success =  true' "$log"; then
  echo "FAIL: the playback did not finish successfully:"
  cat "$log"
  kill "$pid" 2>/dev/null
  exit 1
fi
sleep 3 # the last renders
import -window root "$work/screen.png"
kill "$pid" 2>/dev/null
wait "$pid" 2>/dev/null
# ParaView's window without settings: 1100 x 730 at the top left of the screen; its status bar is
# the last 30 rows.
convert "$work/screen.png" -crop 1100x700+0+0 +repage "$shot"
grep -v '^$' "$log" | grep -v 'INFO|' | sed 's/^/  paraview: /'
if [ ! -f "$baseline" ]; then
  echo "FAIL: no baseline $baseline (this run's screenshot: $shot)"
  exit 1
fi
differing=$(compare -metric AE -fuzz 10% "$shot" "$baseline" "$work/diff.png" 2>&1 >/dev/null)
total=$((1100 * 700))
echo "screenshot $shot: $differing of $total pixels differ from $baseline (diff: $work/diff.png)"
awk -v d="$differing" -v t="$total" -v m="$max_share" 'BEGIN { exit !(d + 0 == d && d / t <= m) }' ||
  { echo "FAIL: more than $max_share of the pixels differ"; exit 1; }
echo "passed"

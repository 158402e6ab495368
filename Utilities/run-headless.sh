#!/usr/bin/env bash
# Runs a command under a private Xvfb. The server picks a free display itself (-displayfd) and
# reports it once it accepts connections, so concurrent or back-to-back runs cannot race for a
# display number the way `xvfb-run -a` can. -noreset: by default Xvfb resets when its last client
# disconnects, and a connection made during the reset fails ("bad X server connection"), which
# ParaView's capability probe (a window opened and closed) followed by the render window hit
# under load.
#   run-headless.sh COMMAND [ARGS...]
set -uo pipefail
tmp=$(mktemp -d)
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp -noreset 3>"$tmp/display" 2>"$tmp/xvfb.log" &
xvfb=$!
for _ in $(seq 200); do
  [ -s "$tmp/display" ] && break
  if ! kill -0 "$xvfb" 2>/dev/null; then
    echo "run-headless: Xvfb did not start:" >&2
    cat "$tmp/xvfb.log" >&2
    rm -rf "$tmp"
    exit 1
  fi
  sleep 0.05
done
if [ ! -s "$tmp/display" ]; then
  echo "run-headless: Xvfb gave no display within 10 s" >&2
  kill "$xvfb" 2>/dev/null
  rm -rf "$tmp"
  exit 1
fi
export DISPLAY=":$(tr -d '[:space:]' <"$tmp/display")"
"$@"
rc=$?
kill "$xvfb" 2>/dev/null
wait "$xvfb" 2>/dev/null
rm -rf "$tmp"
exit $rc

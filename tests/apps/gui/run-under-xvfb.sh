#!/usr/bin/env bash
# Runs pm-slam-app --gui RUNS times in a virtual X server (Xvfb), presses a key in the window
# once the run has printed its summary, and prints "run N exit STATUS" per run; each run's
# stdout goes to OUT/N.stdout. Used by test_gui (tests/apps/test_gui.cpp).
#   run-under-xvfb.sh APP LOG OUT RUNS
set -u
app=$1 log=$2 out=$3 runs=$4
if [ "${5:-}" != inside ]; then
  exec xvfb-run -a -s '-screen 0 1024x768x24' "$0" "$app" "$log" "$out" "$runs" inside
fi
# The map window is titled "pm-slam-app: LOG" (a hidden toolkit window is titled "pm-slam-app"): focused, it
# gets the key as a user's (XTEST), which the window counts; a key sent to a window directly is not.
press_key() {
  local w; w=$(xdotool search --name 'pm-slam-app: ' 2>/dev/null | head -1)
  [ -n "$w" ] && xdotool windowfocus --sync "$w" key space >/dev/null 2>&1
}
for n in $(seq 1 "$runs"); do
  "$app" --gui --no-progress --max-scans 300 --out "$out/$n" "$log" >"$out/$n.stdout" 2>"$out/$n.stderr" &
  pid=$!
  for _ in $(seq 1 150); do grep -q 'Close the window' "$out/$n.stdout" 2>/dev/null && break; sleep 0.2; done
  for _ in $(seq 1 25); do press_key && break; sleep 0.2; done
  wait "$pid"; echo "run $n exit $?"
done

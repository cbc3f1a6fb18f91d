#!/usr/bin/env bash
# pm-slam-app --gui in a virtual X server (Xvfb), stdin not a terminal: once the run has printed its summary,
# the final map must stay shown until a key is pressed in the window. Prints "running N s after the end: yes|no",
# then presses a key and prints "ended after the key: yes|no" and "exit STATUS". Used by test_gui.
#   stays-open-under-xvfb.sh APP LOG OUT SECONDS
set -u
app=$1 log=$2 out=$3 seconds=$4
if [ "${5:-}" != inside ]; then
  exec xvfb-run -a -s '-screen 0 1024x768x24' "$0" "$app" "$log" "$out" "$seconds" inside
fi
"$app" --gui --no-progress --max-scans 100 --out "$out/run" "$log" </dev/null >"$out/stdout" 2>"$out/stderr" &
pid=$!
for _ in $(seq 1 300); do grep -q 'Close the window' "$out/stdout" 2>/dev/null && break; sleep 0.2; done
sleep "$seconds"
kill -0 "$pid" 2>/dev/null && echo "running $seconds s after the end: yes" || echo "running $seconds s after the end: no"
# The map window is titled "pm-slam-app: LOG" (a hidden toolkit window is titled "pm-slam-app").
w=$(xdotool search --name 'pm-slam-app: ' 2>/dev/null | head -1)
[ -n "$w" ] && xdotool windowfocus --sync "$w" key space >/dev/null 2>&1
for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$pid" 2>/dev/null; then
  echo "ended after the key: no"
  kill -KILL "$pid"
else
  echo "ended after the key: yes"
fi
wait "$pid"; echo "exit $?"

#!/usr/bin/env bash
# Sessions on the benchmark logs: each Carmen log cut at its middle line is mapped as two sessions
# (pm-slam-app a.clf --out A; pm-slam-app b.clf --continue A --out AB, the second start searched on A's map)
# and as one run of the whole log; both are scored on the whole log's relations (those across the cut
# included). Also the cost of loading a whole log's session: a --continue run of one scan less the same run
# without --continue (3 runs each). Writes bench/results/sessions.md.
#   bench/sessions.sh [DATASETS_DIR]      (default: ../shared/datasets next to the repository)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
datasets="${1:-$repo/../shared/datasets}"
build="$repo/build"; bin="$build/bin"; work="$build/bench-sessions"
"$repo/scripts/setup.sh" "$build" >/dev/null
cmake --build "$build" -j2 --target pm-slam-app pm-slam-eval >/dev/null
mkdir -p "$work" "$repo/bench/results"
out="$repo/bench/results/sessions.md"
err() { "$bin/pm-slam-eval" "$1" "$2" | awk '/^translational error/ {print $4}'; }
now() { date +%s.%N; }
{
  echo "# Sessions (\`bench/sessions.sh\`, $(date -u +%Y-%m-%d), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
  echo
  echo "| log | one run (m) | two sessions (m) | second start found | loading a whole log's session (s, 3 runs) |"
  echo "|---|---:|---:|---|---|"
} > "$out"
for d in intel aces fr079; do
  log="$datasets/$d/$d.clf"
  [ -f "$log" ] || { echo "skipping $d: $log not found" >&2; continue; }
  half=$(( $(wc -l < "$log") / 2 ))
  head -n "$half" "$log" > "$work/$d-a.clf"
  tail -n "+$((half + 1))" "$log" > "$work/$d-b.clf"
  "$bin/pm-slam-app" --quiet --no-progress "$log" --out "$work/$d-one"
  "$bin/pm-slam-app" --quiet --no-progress "$work/$d-a.clf" --out "$work/$d-A"
  start=$("$bin/pm-slam-app" --no-progress "$work/$d-b.clf" --continue "$work/$d-A" --out "$work/$d-AB" 2>&1 >/dev/null |
          sed -n 's/.*start found at .* after \([0-9]*\) scans.*/after \1 scans/p')
  loads=""
  for k in 1 2 3; do
    t0=$(now); "$bin/pm-slam-app" --quiet --no-progress "$work/$d-b.clf" --max-scans 1 --out "$work/x1" >/dev/null 2>&1
    t1=$(now); "$bin/pm-slam-app" --quiet --no-progress "$work/$d-b.clf" --max-scans 1 --continue "$work/$d-one" \
      --initial-pose=0,0,0 --out "$work/x2" >/dev/null 2>&1 || true
    t2=$(now); loads="$loads $(echo "($t2 - $t1) - ($t1 - $t0)" | bc -l | xargs printf '%.2f')"
  done
  echo "| $d | $(err "$work/$d-one/trajectory.txt" "$datasets/$d/$d.relations") | $(err "$work/$d-AB/trajectory.txt" "$datasets/$d/$d.relations") | $start |$loads |" >> "$out"
done
cat "$out"

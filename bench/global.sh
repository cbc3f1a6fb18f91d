#!/usr/bin/env bash
# Global localisation on the benchmark logs' maps: for intel, aces and fr079, pm-slam-app maps the log
# (the reference trajectory and the map), then pm-global-localization searches the start without a start
# pose from STARTS scans spread over the log (default 100) and compares each answer with the SLAM run.
# Writes bench/results/global.md.
#   bench/global.sh [DATASETS_DIR]      (default: ../shared/datasets next to the repository)
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
datasets="${1:-$repo/../shared/datasets}"
build="$repo/build"; bin="$build/bin"; work="$build/bench-global"
starts="${STARTS:-100}"
"$repo/scripts/setup.sh" "$build" >/dev/null
cmake --build "$build" -j2 --target pm-slam-app pm-global-localization >/dev/null
mkdir -p "$work" "$repo/bench/results"
out="$repo/bench/results/global.md"
{
  echo "# Global localisation (\`bench/global.sh\`, $(date -u +%Y-%m-%d), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
  echo
  echo "From $starts start scans spread over each log, the start is searched on the log's own map (the SLAM run's"
  echo "output folder) without a start pose; found = decided within 0.3 m and 5 deg of the SLAM run's pose of that scan,"
  echo "wrong = decided elsewhere, undecided = no decision. Scans needed: from the start scan to the decision."
  echo "Search time: one whole-map branch-and-bound search (mean / max over the starts)."
  echo
  echo "| log | starts | found / wrong / undecided | scans needed (median / max) | whole-map search | map area |"
  echo "|---|---:|---|---|---|---:|"
} > "$out"
for d in intel aces fr079; do
  [ -f "$datasets/$d/$d.clf" ] || { echo "skipping $d: $datasets/$d/$d.clf not found" >&2; continue; }
  "$bin/pm-slam-app" --quiet --no-progress "$datasets/$d/$d.clf" --out "$work/$d" >/dev/null
  "$bin/pm-global-localization" "$work/$d" "$datasets/$d/$d.clf" "$work/$d/trajectory.txt" --starts "$starts" \
    2>"$work/$d.wrong.txt" | sed "s|$datasets/||" >> "$out"
done
cat "$out"

#!/usr/bin/env bash
# Memory benchmark: peak RSS and the map's own bytes of pm-slam-app (default configuration) on the Freiburg logs
# and on generated worlds whose area grows while their bounding box does not.
#
#   bench/memory.sh [DATASETS_DIR]      (default: ../shared/datasets next to the repository)
#
# Worlds (pm-world-log, bench/world_log.cpp): a 1 km x 1 km campus (a loop of 3 m corridors at 45 degrees to the
# first pose, 2.9 km of driving), mapped after 25, 50, 75 and 100 % of its log, and an open 60 m x 40 m hall.
# Each run reports: peak RSS (/usr/bin/time -v), the area observed (cells with evidence), the bounding box of the
# map, the grid's and the distance layer's bytes, the loop closure's bytes, ms/scan, and the error against the
# ground truth. The three logs also run with PMSLAM_KEEP_LIBRARY_PAGES=1 (start-up library pages kept; a hook of
# pm-slam-app-instrumented, the same program with the test and benchmark hooks), and MRPT's
# own floor (bench/mrpt_memory_floor.cpp) is measured beside them.
# Writes bench/results/memory.md and bench/results/memory.png (map bytes against area observed).
# Exit status: 0 done, 1 a run failed, 2 bad input.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
datasets="${1:-$repo/../shared/datasets}"
build="$repo/build"
bin="$build/bin"
work="$build/bench-runs/memory"
results="$repo/bench/results"

die() { echo "bench/memory.sh: $*" >&2; exit 2; }
note() { echo "[memory] $*" >&2; }
[ $# -le 1 ] || die "usage: bench/memory.sh [DATASETS_DIR]"
for tool in cmake gnuplot awk; do command -v "$tool" >/dev/null || die "'$tool' is not installed"; done
[ -x /usr/bin/time ] && /usr/bin/time -v true >/dev/null 2>&1 || die "/usr/bin/time -v is needed (package time)"

note "building Release in $build"
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build/memory-build.log" 2>&1 || die "cmake failed ($build/memory-build.log)"
cmake --build "$build" -j2 --target pm-slam-app pm-slam-app-instrumented pm-slam-eval pm-world-log mrpt-memory-floor-maps >>"$build/memory-build.log" 2>&1 \
  || die "build failed ($build/memory-build.log)"
rm -rf "$work"
mkdir -p "$work" "$results"

note "generating the worlds"
"$bin/pm-world-log" campus "$work/campus.clf"
"$bin/pm-world-log" hall "$work/hall.clf"
campus_scans=$(grep -c '^FLASER' "$work/campus.clf")

rows="$work/rows.tsv"   # name scans peak_mb area_m2 bbox_m2 grid_mb dist_mb lc_mb own_mb ms_mean ms_median ms_p99 trans_err released_mb
: >"$rows"
failed=0
# run NAME LOG RELATIONS [extra pm-slam-app args...]; app=PROGRAM in its environment runs that program instead
run() {
  local name=$1 log=$2 rel=$3; shift 3
  local out="$work/$name"
  note "$name"
  if ! /usr/bin/time -v "$bin/${app:-pm-slam-app}" "$log" --out "$out" --no-progress "$@" >"$out.summary" 2>"$out.time"; then
    local rc=$?
    [ $rc = 3 ] || { note "warning: $name failed (exit $rc; $out.summary, $out.time)"; failed=1; return; }
  fi
  local peak; peak=$(awk '/Maximum resident set size/ {printf "%.1f", $NF/1024}' "$out.time")
  local err="-"
  [ -n "$rel" ] && err=$("$bin/pm-slam-eval" "$out/trajectory.txt" "$rel" 2>/dev/null | awk '/^translational error/ {print $4}')
  # "peak memory P MB (at the end: O MB own, F MB mapped library files, R MB of start-up library pages given back;
  #  map: A m² observed, grid G MB + distance layer D MB[, loop closure L MB])"
  local mem; mem=$(grep 'peak memory' "$out.summary")
  local own grid dist lc area released
  own=$(sed -E 's/.*at the end: ([0-9.]+) MB own.*/\1/' <<<"$mem")
  released=$(sed -E 's/.* ([0-9.]+) MB of start-up library pages.*/\1/' <<<"$mem")
  area=$(sed -E 's/.*map: ([0-9.]+) m.*/\1/' <<<"$mem")
  grid=$(sed -E 's/.*grid ([0-9.]+) MB.*/\1/' <<<"$mem")
  dist=$(sed -E 's/.*distance layer ([0-9.]+) MB.*/\1/' <<<"$mem")
  lc=$(grep -q 'loop closure [0-9.]* MB' <<<"$mem" && sed -E 's/.*loop closure ([0-9.]+) MB.*/\1/' <<<"$mem" || echo 0)
  local t; t=$(grep 'time per scan' "$out.summary" | sed -E 's/.*mean ([0-9.]+) ms, median ([0-9.]+) ms, p99 ([0-9.]+) ms.*/\1 \2 \3/')
  local scans; scans=$(awk '/^ *scans [0-9]+/ {print $2; exit}' "$out.summary" | tr -d ,)
  # Bounding box of the map: map.yaml's resolution and map.pgm's size (the cells with evidence, plus 10).
  local bbox; bbox=$(head -c 200 "$out/map.pgm" | sed -n 3p | awk '{print $1 * $2}')
  local res; res=$(awk '/^resolution:/ {print $2}' "$out/map.yaml")
  bbox=$(awk -v n="$bbox" -v r="$res" 'BEGIN {printf "%.0f", n * r * r}')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$scans" "$peak" "$area" "$bbox" "$grid" "$dist" "$lc" \
    "$own" $t "$err" "$released" >>"$rows"
}

for f in 25 50 75 100; do
  run "campus-$f" "$work/campus.clf" "$work/campus.relations" --max-scans $((campus_scans * f / 100))
done
run hall "$work/hall.clf" "$work/hall.relations"
logs=()
for d in intel aces fr079; do
  if [ -f "$datasets/$d/$d.clf" ]; then
    logs+=("$d")
    run "$d" "$datasets/$d/$d.clf" "$datasets/$d/$d.relations"
    PMSLAM_KEEP_LIBRARY_PAGES=1 app=pm-slam-app-instrumented run "$d-keep-pages" "$datasets/$d/$d.clf" "$datasets/$d/$d.relations"
  else
    note "warning: $datasets/$d/$d.clf missing: $d skipped"
  fi
done
floor=$(/usr/bin/time -v "$bin/mrpt-memory-floor-maps" 2>&1 >/dev/null | awk '/Maximum resident set size/ {printf "%.1f", $NF/1024}')

# What each shared library costs at start-up: pm-slam-app's /proc/self/smaps just before it gives the start-up
# pages back and just after (PMSLAM_SMAPS_DUMP, a hook of pm-slam-app-instrumented), summed per mapped file.
sample_log="$work/hall.clf"
PMSLAM_SMAPS_DUMP="$work/smaps" "$bin/pm-slam-app-instrumented" "$sample_log" --out "$work/smaps-run" --no-progress --quiet >/dev/null 2>&1 || true
per_file() {  # FILE -> "path rss_kb anon_kb" per mapped file
  awk '/^[0-9a-f]+-[0-9a-f]+ / {path = (NF >= 6 ? $6 : "[anonymous]"); next}
       /^Rss:/ {rss[path] += $2} /^Anonymous:/ {anon[path] += $2}
       END {for (p in rss) print p, rss[p], anon[p]}' "$1"
}
libtable="$work/libraries.tsv"
if [ -f "$work/smaps.before" ] && [ -f "$work/smaps.after" ]; then
  join -a1 -e0 -o '0,1.2,1.3,2.2' <(per_file "$work/smaps.before" | sort) <(per_file "$work/smaps.after" | sort) \
    | sort -k2,2nr >"$libtable"
else
  note "warning: no smaps dump (PMSLAM_SMAPS_DUMP): library table skipped"
  : >"$libtable"
fi

# --- report --------------------------------------------------------------------------------------------------------
md="$results/memory.md"
{
  echo "# pmslam memory: peak RSS and map bytes against the area mapped"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'); commit $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo '?')"
  echo "- command: \`bench/memory.sh\`; Release build; pm-slam-app with config/default.ini (loop closure on)"
  echo "- peak RSS: \`/usr/bin/time -v\`; map bytes, area observed (cells with evidence) and loop-closure bytes:"
  echo "  pm-slam-app's summary; bounding box: the extent of map.pgm (evidence + 10 cells)"
  echo "- MRPT's floor (a program that only creates an empty COccupancyGridMap2D): $floor MB"
  echo
  echo "| run | scans | peak RSS [MB] | area observed [m²] | bounding box [m²] | grid [MB] | distance layer [MB] | map bytes / m² | loop closure [MB] | own at end [MB] | ms/scan mean | median | p99 | trans. error [m] | start-up pages given back [MB] |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"
  awk -F'\t' '{printf "| %s | %s | %s | %s | %s | %s | %s | %.0f | %s | %s | %s | %s | %s | %s | %s |\n",
    $1, $2, $3, $4, $5, $6, $7, ($6 + $7) * 1048576 / ($4 > 0 ? $4 : 1), $8, $9, $10, $11, $12, $13, $14}' "$rows"
  echo
  echo "## What each mapped file costs at start-up"
  echo
  echo "pm-slam-app's resident pages per mapped file, read from /proc/self/smaps just before and just after it gives"
  echo "back the pages only start-up needed (util/LibraryPages.h: read-only file pages that hold no private page);"
  echo "'private' is what the loader wrote (relocated data) and stays. The ${#logs[@]} logs above ran with and without"
  echo "giving the pages back (\`-keep-pages\` rows: PMSLAM_KEEP_LIBRARY_PAGES=1)."
  echo
  awk '$1 ~ /^\// {n++; r += $2; a += $3; f += $4} $1 !~ /^\// {o += $2}
       END {printf "- %d mapped files: %.1f MB resident at start-up (%.1f MB private), %.1f MB after; heap, stacks and other anonymous memory %.1f MB\n", n, r/1024, a/1024, f/1024, o/1024}' "$libtable"
  echo
  echo "| file | resident at start-up [MB] | of it private [MB] | resident after [MB] |"
  echo "|---|---:|---:|---:|"
  awk '$1 ~ /^\// && NR <= 40 {n = split($1, parts, "/"); printf "| %s | %.2f | %.2f | %.2f |\n", parts[n], $2/1024, $3/1024, $4/1024}' "$libtable" | head -n 25
} >"$md"

awk -F'\t' '$1 ~ /^campus/ {print $4, ($6 + $7)}' "$rows" >"$work/campus.dat"
awk -F'\t' '$1 !~ /^campus/ && $1 !~ /keep-pages/ {print $4, ($6 + $7), $1}' "$rows" >"$work/others.dat"
gnuplot <<GP
set terminal pngcairo size 900,600
set output "$results/memory.png"
set title "pmslam: map bytes (grid + distance layer) against the area observed"
set xlabel "area observed [m²]"
set ylabel "map [MB]"
set key left top
set grid
set fit logfile "$work/fit.log"  # not fit.log in the folder the script is run from
f(x) = a * x
fit f(x) "$work/campus.dat" using 1:2 via a
plot "$work/campus.dat" using 1:2 with linespoints pt 7 title "1 km² campus after 25/50/75/100 % of its log", \
     f(x) with lines dt 2 title sprintf("linear fit: %.1f KB/m²", a * 1024), \
     "$work/others.dat" using 1:2:3 with labels point pt 5 offset 1,1 notitle
GP
note "wrote $md and $results/memory.png"
exit $failed

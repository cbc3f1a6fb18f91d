#!/usr/bin/env bash
# Speed benchmark: pmslam as it is now against a yardstick build of an earlier revision, its front-end alone and
# MRPT's ICP-SLAM, side by side on the same machine, on the Freiburg logs and on a generated large building.
#
#   bench/speed.sh [DATASETS_DIR]      (default: ../shared/datasets next to the repository)
#
# Environment:
#   BASE=REV     the yardstick revision, built from `git archive REV` in build/speed-base/ (default 52bf27a,
#                the build the speed issue was measured against); BASE=none: no yardstick
#   ROUNDS=N     rounds of pmslam runs (default 3); the systems alternate within a round, so a slower spell of
#                the machine falls on all of them; the table holds the median over the rounds
#   ICP=0        skip the ICP peer (it runs once per log: it is 20-40x slower)
#
# Logs: intel, aces, fr079 from DATASETS_DIR (each skipped when absent) and `hospital`, written by
# `pm-world-log hospital`: a 120 m x 60 m floor of long corridors with glass and two 10 s logging gaps.
#
# Per run: time per scan from the program's timing.txt (pmslam: match + map update, the front-end's own work;
# the ICP peer: processObservation), whole-log wall time, realtime factor (log time / wall time), peak RSS
# (/usr/bin/time -v), the error (pm-slam-eval, Kuemmerle et al.), and pmslam's split of its SLAM time into
# front-end and waiting for the loop-closure back-end.
# Writes bench/results/speed.md (table) and bench/results/speed_<log>.png (ms per scan along each log);
# raw runs in build/speed-runs/. Exit status: 0 done, 1 a run failed (results still written), 2 bad input.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
datasets="${1:-$repo/../shared/datasets}"
base_rev="${BASE:-52bf27a}"
rounds="${ROUNDS:-3}"
run_icp="${ICP:-1}"
build="$repo/build"
bin="$build/bin"
work="$build/speed-runs"
results="$repo/bench/results"

die() { echo "bench/speed.sh: $*" >&2; exit 2; }
note() { echo "[speed] $*" >&2; }
[ $# -le 1 ] || die "usage: bench/speed.sh [DATASETS_DIR]"
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || die "ROUNDS='$rounds': expected a whole number >= 1"
for tool in cmake gnuplot awk git; do command -v "$tool" >/dev/null || die "'$tool' is not installed"; done
[ -x /usr/bin/time ] && /usr/bin/time -v true >/dev/null 2>&1 || die "/usr/bin/time -v is needed for the peak RSS (package 'time')"

# --- builds ---------------------------------------------------------------------------------------------------------
note "building Release in $build"
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target pm-slam-app pm-icp-slam pm-slam-eval pm-world-log >/dev/null
base_bin=""
if [ "$base_rev" != none ]; then
  base_hash=$(git -C "$repo" rev-parse --verify --quiet "$base_rev^{commit}") || die "BASE='$base_rev': not a revision of this repository"
  base_dir="$build/speed-base"
  base_bin="$base_dir/build/bin/pm-slam-app"
  if [ "$(cat "$base_dir/revision" 2>/dev/null)" != "$base_hash" ] || [ ! -x "$base_bin" ]; then
    note "building the yardstick $base_rev in $base_dir (once per revision)"
    rm -rf "$base_dir"; mkdir -p "$base_dir/src"
    git -C "$repo" archive "$base_hash" | tar -x -C "$base_dir/src"
    cmake -S "$base_dir/src" -B "$base_dir/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$base_dir/build" -j2 --target pm-slam-app >/dev/null
    echo "$base_hash" >"$base_dir/revision"
  fi
fi

# --- logs -----------------------------------------------------------------------------------------------------------
rm -rf "$work"; mkdir -p "$work/logs" "$results"
logs=()
declare -A log_file relations_file
for d in intel aces fr079; do
  if [ -f "$datasets/$d/$d.clf" ] && [ -f "$datasets/$d/$d.relations" ]; then
    logs+=("$d"); log_file[$d]="$datasets/$d/$d.clf"; relations_file[$d]="$datasets/$d/$d.relations"
  else note "warning: $datasets/$d/$d.clf or .relations missing: $d skipped"; fi
done
"$bin/pm-world-log" hospital "$work/logs/hospital.clf"
logs+=(hospital); log_file[hospital]="$work/logs/hospital.clf"; relations_file[hospital]="$work/logs/hospital.relations"

# --- runs -----------------------------------------------------------------------------------------------------------
# timing_stats FILE COLUMN: "n mean median p99" of a per-scan time column (comments skipped)
timing_stats() {
  awk -v c="$2" '!/^#/ && NF>=c {print $c}' "$1" | sort -g | awk '
    {v[NR]=$1; s+=$1}
    END { if (NR==0) {print "0 0 0 0"; exit}
          k50=int(0.5*(NR-1)+0.5)+1; k99=int(0.99*(NR-1)+0.5)+1
          printf "%d %.4f %.4f %.4f\n", NR, s/NR, v[k50], v[k99] }'
}
# log_span FILE: seconds between the first and the last pose of a trajectory
log_span() { awk '!/^#/ && NF>=4 { if (!n++) {lo=$1; hi=$1} if ($1<lo) lo=$1; if ($1>hi) hi=$1 } END {printf "%.3f\n", hi-lo}' "$1"; }
# slam_split STDOUT: "front-end-seconds waiting-seconds" from pmslam's summary ("- -" when absent)
slam_split() {
  sed -n 's/.*SLAM time [0-9.]* s (front-end \([0-9.]*\) s, waiting for the back-end \([0-9.]*\) s).*/\1 \2/p' "$1" | tail -n 1 | grep . || echo "- -"
}

failed=0
# run SYSTEM LOG ROUND TIMING_COLUMN -- COMMAND...: one run; appends a row to $work/LOG/SYSTEM.rows:
#   mean median p99 wall realtime rss error frontend_s wait_s scans
run() {
  local sys=$1 d=$2 r=$3 col=$4; shift 5
  local out="$work/$d/$sys-$r" rc=0 t0 t1
  mkdir -p "$out"
  t0=$(date +%s.%N)
  /usr/bin/time -v -o "$out/time.txt" "$@" --out "$out" >"$out/stdout.txt" 2>&1 || rc=$?
  t1=$(date +%s.%N)
  if [ $rc != 0 ] && [ $rc != 3 ] || [ ! -s "$out/trajectory.txt" ]; then  # 3: ran to the end, lost somewhere
    note "$d: $sys round $r FAILED (exit $rc): $(tail -n 2 "$out/stdout.txt" | tr '\n' ' ')"; failed=1; return 0
  fi
  local err wall span
  err=$("$bin/pm-slam-eval" "$out/trajectory.txt" "${relations_file[$d]}" 2>/dev/null | sed -n 's/^translational error \[m\]: \([0-9.]*\).*/\1/p')
  wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.2f", b-a}')
  span=$(log_span "$out/trajectory.txt")
  read -r n mean median p99 < <(timing_stats "$out/timing.txt" "$col")
  echo "$mean $median $p99 $wall $(awk -v s="$span" -v w="$wall" 'BEGIN{printf "%.0f", s/w}')" \
       "$(awk -F: '/Maximum resident set size/ {printf "%.0f", $2/1024}' "$out/time.txt") ${err:--}" \
       "$(slam_split "$out/stdout.txt") $n" >>"$work/$d/$sys.rows"
  note "$d: $sys round $r: $wall s wall, $mean ms/scan, error ${err:--} m"
}

pm_systems=(pmslam pmslam-fe)
[ -z "$base_bin" ] || pm_systems+=(pmslam-base)
for ((r = 1; r <= rounds; ++r)); do
  # Alternate the order from round to round: no system always runs right after the same one.
  order=("${pm_systems[@]}")
  ((r % 2)) || order=($(printf '%s\n' "${pm_systems[@]}" | tac))
  for d in "${logs[@]}"; do
    for s in "${order[@]}"; do
      case $s in
        pmslam) run pmslam "$d" "$r" 4 -- "$bin/pm-slam-app" --no-progress "${log_file[$d]}" ;;
        pmslam-fe) run pmslam-fe "$d" "$r" 4 -- "$bin/pm-slam-app" --no-progress --set LoopClosure.enabled=false "${log_file[$d]}" ;;
        pmslam-base) run pmslam-base "$d" "$r" 4 -- "$base_bin" --no-progress "${log_file[$d]}" ;;
      esac
    done
  done
done
if [ "$run_icp" != 0 ]; then
  for d in "${logs[@]}"; do run icp "$d" 1 2 -- "$bin/pm-icp-slam" --config "$repo/config/icp-slam-tuned.ini" "${log_file[$d]}"; done
fi

# --- table ----------------------------------------------------------------------------------------------------------
# median_col FILE K: the median of column K over the rows (rounds)
median_col() { awk -v k="$2" '$k != "-" {print $k}' "$1" | sort -g | awk '{v[NR]=$1} END {if (NR) print v[int((NR+1)/2)]; else print "-"}'; }
label() {
  case $1 in
    pmslam) echo "pmslam, default configuration" ;;
    pmslam-fe) echo "pmslam front-end alone (LoopClosure.enabled=false)" ;;
    pmslam-base) echo "pmslam at $base_rev (yardstick)" ;;
    icp) echo "MRPT ICP-SLAM, tuned (one run)" ;;
  esac
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN{ if (a == "-" || b == "-" || b == 0) print "-"; else printf "%.2f", a/b }'; }
note "writing $results/speed.md"
cpu=$(awk -F': ' '/^model name/ {print $2; exit}' /proc/cpuinfo 2>/dev/null || true)
commit=$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)
git -C "$repo" diff --quiet HEAD -- . ":(exclude)bench/results" 2>/dev/null || commit="$commit (with uncommitted changes)"
{
  echo "# Speed: pmslam against its yardstick build, its front-end alone and the ICP peer"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'); machine: $(nproc) cores, ${cpu:-unknown CPU}; commit $commit"
  echo "- command: \`bench/speed.sh\` (BASE=$base_rev ROUNDS=$rounds ICP=$run_icp); medians over the rounds"
  echo "- ms/scan: the program's own per-scan time (pmslam: match + map update, without the waits for the"
  echo "  loop-closure back-end, which are in the wall time); wall: the whole run, reading the log and writing the"
  echo "  outputs included; realtime factor: log time / wall time; error: Kuemmerle et al., mean translational (m)"
  echo "- ratios: front-end = mean ms/scan / the yardstick's; wall / front-end = this wall time / the front-end"
  echo "  alone's (what loop closure adds to an offline run)"
  echo
  echo "| log | system | scans | ms/scan mean | median | p99 | wall [s] | realtime | peak RSS [MB] | error [m] | front-end vs yardstick | wall / front-end alone |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  for d in "${logs[@]}"; do
    base_mean=$([ -f "$work/$d/pmslam-base.rows" ] && median_col "$work/$d/pmslam-base.rows" 1 || echo -)
    fe_wall=$([ -f "$work/$d/pmslam-fe.rows" ] && median_col "$work/$d/pmslam-fe.rows" 4 || echo -)
    for s in pmslam pmslam-fe pmslam-base icp; do
      f="$work/$d/$s.rows"
      [ -f "$f" ] || continue
      m=(); for k in 1 2 3 4 5 6 7 10; do m+=("$(median_col "$f" $k)"); done
      vs=$(ratio "${m[0]}" "$base_mean"); wf=$(ratio "${m[3]}" "$fe_wall")
      [ "$s" = icp ] && wf=-
      echo "| $d | $(label $s) | ${m[7]} | ${m[0]} | ${m[1]} | ${m[2]} | ${m[3]} | ${m[4]}x | ${m[5]} | ${m[6]} | $vs | $wf |"
    done
  done
  echo
  echo "pmslam's SLAM time split (medians): front-end s / waiting for the back-end s"
  echo
  for d in "${logs[@]}"; do
    for s in pmslam pmslam-base; do
      f="$work/$d/$s.rows"
      [ -f "$f" ] && echo "- $d, $(label $s): $(median_col "$f" 8) / $(median_col "$f" 9)"
    done
  done
  echo
  for d in "${logs[@]}"; do echo "![$d](speed_$d.png)"; done
} >"$results/speed.md"

# --- plots: ms per scan along each log (round 1), a running mean over 200 scans ------------------------------------------
plot_term='set terminal pngcairo size 900,500 font "Sans,10" noenhanced'
gnuplot -e "$plot_term" >/dev/null 2>&1 || plot_term='set terminal png size 900,500 noenhanced'
for d in "${logs[@]}"; do
  series=()
  for s in pmslam pmslam-base icp; do
    t="$work/$d/$s-1/timing.txt"
    [ -s "$t" ] || continue
    col=4; [ $s = icp ] && col=2
    awk -v c=$col '!/^#/ && NF>=c {i=n%200; if (n>=200) s-=b[i]; b[i]=$c; s+=$c; if (++n>=200) print n, s/200}' "$t" \
      >"$work/$d/$s-1/running.txt"
    series+=("'$work/$d/$s-1/running.txt' using 1:2 with lines lw 2 title '$(label $s)'")
  done
  [ ${#series[@]} -gt 0 ] || continue
  gnuplot <<EOF
$plot_term
set output '$results/speed_$d.png'
set title "$d: time per scan along the log (running mean over 200 scans)"
set xlabel 'scan'; set ylabel 'ms per scan'
set logscale y; set format y '%g'; set grid; set key top left
plot $(IFS=,; echo "${series[*]}")
EOF
done
note "done: $results/speed.md"
exit $failed

#!/usr/bin/env bash
# Fault-injection benchmark: pmslam (and the MRPT ICP-SLAM peer) on the Freiburg logs with the faults a real robot
# log has, injected by pm-fault-inject at two levels and several seeds.
#
#   bench/robustness.sh [DATASETS_DIR]      (default: ../shared/datasets next to the repository)
#
# Environment: SEEDS (default "1 2 3 4 5": three seeds hid runs that a fourth broke by metres, decisions.md D59),
# SET="SECTION.KEY=VALUE ..." to run pmslam with those keys overridden
# (e.g. SET=LoopClosure.enabled=false for the front-end alone; the clean row too), ICP=0 to skip the ICP peer (it runs on level a, first seed, of every
# fault: it is 20-40x slower), ICP=reuse to keep the peer's results from the previous run in build/ and run only
# those missing (the peer and the injected logs do not change with pmslam), FAULTS to run a subset (names in bench/faults.txt),
# LEVELS (default "a b"; "c": harder levels than the targets are stated for, to find where pmslam breaks next).
# Writes bench/results/robustness.md (table) and bench/results/robustness.png (error / clean error per fault);
# with other LEVELS, robustness-<levels>.md and .png (e.g. robustness-c.md);
# raw runs in build/robustness-runs/. Exit status: 0 done, 1 a run failed (results still written), 2 bad input.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
datasets="${1:-$repo/../shared/datasets}"
seeds=(${SEEDS:-1 2 3 4 5})
run_icp="${ICP:-1}"
set_args=()
for kv in ${SET:-}; do set_args+=(--set "$kv"); done
build="$repo/build"
bin="$build/bin"
work="$build/robustness-runs"
results="$repo/bench/results"
names=(intel aces fr079)

die() { echo "bench/robustness.sh: $*" >&2; exit 2; }
note() { echo "[robustness] $*" >&2; }
[ -d "$datasets" ] || die "datasets folder '$datasets' not found (give it as the first argument)"
datasets="$(cd "$datasets" && pwd)"
for tool in cmake gnuplot awk; do command -v "$tool" >/dev/null || die "'$tool' is not installed"; done

# The faults (name|pm-fault-inject arguments|what it models), shared with bench/compare.sh.
[ -f "$repo/bench/faults.txt" ] || die "bench/faults.txt is missing"
faults=()
while IFS= read -r line; do [[ -z "$line" || "$line" == \#* ]] || faults+=("$line"); done <"$repo/bench/faults.txt"
levels="${LEVELS:-a b}"
keep=()
for f in "${faults[@]}"; do name="${f%%|*}"; for l in $levels; do [ "${name##*-}" = "$l" ] && keep+=("$f"); done; done
faults=("${keep[@]}")
[ ${#faults[@]} -gt 0 ] || die "LEVELS='$levels': expected some of a b c"
suffix=""; [ "$levels" = "a b" ] || suffix="-$(echo "$levels" | tr -d ' ')"
if [ -n "${FAULTS:-}" ]; then
  keep=()
  for f in "${faults[@]}"; do for w in $FAULTS; do [ "${f%%|*}" = "$w" ] && keep+=("$f"); done; done
  faults=("${keep[@]}")
fi

note "building Release in $build"
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target pm-slam-app pm-fault-inject pm-icp-slam pm-slam-eval >/dev/null
# A fresh run folder; with ICP=reuse only the peer's rows of the previous run stay in it.
if [ "$run_icp" = reuse ] && [ -d "$work" ]; then find "$work" -type f ! -path '*/icp/row' -delete; else rm -rf "$work"; fi
mkdir -p "$work" "$results"
# The configuration as it is now: edits made while the benchmark runs do not mix into it.
config="$work/default.ini"
cp "$repo/config/default.ini" "$config"

json_num() { tr ',{}' '\n\n\n' <"$2" | awk -F: -v k="\"$1\"" '{gsub(/ /,"",$1)} $1==k {gsub(/ /,"",$2); print $2; exit}'; }
# stats TIMING COLUMN: mean ms per scan; matched fraction (pmslam: accepted / attempted matches)
mean_ms() { awk -v c="$2" '!/^#/ && NF>=c {s+=$c; n++} END {printf "%.3f", n ? s/n : 0}' "$1"; }
matched_fraction() { awk '!/^#/ && NF>=9 && $9!=1 {n++; if ($9!=3) m++} END {printf "%.3f", n ? m/n : 0}' "$1"; }

r4() { awk -v a="$1" 'BEGIN{ if (a == "nan" || a == "") print "failed"; else printf "%.4f", a}'; }

failed=0
# run SYSTEM LOG OUT: one run; writes OUT/row = "trans rot ms matched"
run() {
  local sys=$1 log=$2 out=$3 d=$4 rc=0
  mkdir -p "$out"
  if [ "$sys" = pmslam ]; then
    "$bin/pm-slam-app" --config "$config" "${set_args[@]}" --no-progress --max-untracked 1e9 "$log" --out "$out" \
      >"$out/stdout.txt" 2>"$out/stderr.txt" || rc=$?
  else
    "$bin/pm-icp-slam" --config "$repo/config/icp-slam-tuned.ini" "$log" --out "$out" >"$out/stdout.txt" 2>"$out/stderr.txt" || rc=$?
  fi
  if [ $rc != 0 ] || ! "$bin/pm-slam-eval" --json "$out/trajectory.txt" "$datasets/$d/$d.relations" >"$out/eval.json" 2>/dev/null; then
    note "$sys on $log failed (exit $rc)"; echo "nan nan nan nan" >"$out/row"; failed=1; return 0
  fi
  local col=4 mf=1
  [ "$sys" = pmslam ] || col=2
  [ "$sys" = pmslam ] && mf=$(matched_fraction "$out/timing.txt")
  echo "$(json_num trans_mean_m "$out/eval.json") $(json_num rot_mean_deg "$out/eval.json") $(mean_ms "$out/timing.txt" $col) $mf" >"$out/row"
}

# icp_needed DIR: the ICP peer is to run into DIR (not with ICP=0, nor with ICP=reuse when DIR has its row)
icp_needed() { [ "$run_icp" != 0 ] && ! { [ "$run_icp" = reuse ] && [ -s "$1/row" ]; }; }

present=()
for d in "${names[@]}"; do
  [ -f "$datasets/$d/$d.clf" ] && [ -f "$datasets/$d/$d.relations" ] && present+=("$d") || note "$d missing: skipped"
done
[ ${#present[@]} -gt 0 ] || die "no dataset in '$datasets'"

for d in "${present[@]}"; do
  note "$d: clean"
  run pmslam "$datasets/$d/$d.clf" "$work/$d/clean/pmslam" "$d"
  icp_needed "$work/$d/clean/icp" && run icp "$datasets/$d/$d.clf" "$work/$d/clean/icp" "$d"
  for f in "${faults[@]}"; do
    IFS='|' read -r name fargs _ <<<"$f"
    for s in "${seeds[@]}"; do
      dir="$work/$d/$name/s$s"; mkdir -p "$dir"
      # shellcheck disable=SC2086
      "$bin/pm-fault-inject" $fargs --seed "$s" "$datasets/$d/$d.clf" "$dir/log.clf" 2>"$dir/faults.txt" \
        || { note "pm-fault-inject $fargs failed"; failed=1; continue; }
      note "$d: $name seed $s"
      run pmslam "$dir/log.clf" "$dir/pmslam" "$d"
      if icp_needed "$dir/icp" && [ "$s" = "${seeds[0]}" ] && [ "${name%-a}" != "$name" ]; then
        run icp "$dir/log.clf" "$dir/icp" "$d"
      fi
      rm -f "$dir/log.clf"
    done
  done
done

# --- table --------------------------------------------------------------------------------------------------------
commit=$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)
git -C "$repo" diff --quiet HEAD -- . ":(exclude)bench/results" 2>/dev/null || commit="$commit (with uncommitted changes)"
plotdata="$work/plot.txt"; : >"$plotdata"
{
  echo "# pmslam under injected faults"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'); command: \`bench/robustness.sh\` (SEEDS=\"${seeds[*]}\"${SET:+, SET=\"$SET\"}${LEVELS:+, LEVELS=\"$LEVELS\"}), commit $commit"
  echo "- each fault injected by \`pm-fault-inject\` into the Carmen log; error = Kuemmerle et al. relative metric"
  echo "  (mean translational error, m) over the relations whose scans are in the faulted log; ratio = error / clean error."
  echo "- pmslam: worst and median over the seeds; ms/scan and matched fraction (accepted / attempted matches) of the worst seed."
  echo "- ICP peer (MRPT CMetricMapBuilderICP, config/icp-slam-tuned.ini): level a, first seed only."
  echo
  echo "| fault | what | log | pmslam clean | pmslam worst (ratio) | pmslam median | ms/scan | matched | ICP clean | ICP faulted (ratio) |"
  echo "|---|---|---|---:|---:|---:|---:|---:|---:|---:|"
  for f in "${faults[@]}"; do
    IFS='|' read -r name _ what <<<"$f"
    for d in "${present[@]}"; do
      read -r c _ cms _ <"$work/$d/clean/pmslam/row"
      worst=-1; wrow=""; errs=()
      for s in "${seeds[@]}"; do
        r="$work/$d/$name/s$s/pmslam/row"; [ -f "$r" ] || continue
        read -r e _ ms mf <"$r"; errs+=("$e")
        if [ "$e" = nan ] || awk -v a="$e" -v b="$worst" 'BEGIN{exit !(a>b)}'; then worst=$e; wrow="$ms $mf"; fi
      done
      med=$(printf '%s\n' "${errs[@]}" | sort -g | awk '{v[NR]=$1} END {print (NR%2 ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2)}')
      ratio=$(awk -v a="$worst" -v b="$c" 'BEGIN{printf "%.2f", (b>0 ? a/b : 0)}')
      icpc="-"; icpf="-"
      if [ -f "$work/$d/clean/icp/row" ] && [ -f "$work/$d/$name/s${seeds[0]}/icp/row" ]; then
        read -r ic _ <"$work/$d/clean/icp/row"; read -r iff _ <"$work/$d/$name/s${seeds[0]}/icp/row"
        icpc=$(r4 "$ic"); icpf="$(r4 "$iff") ($(awk -v a="$iff" -v b="$ic" 'BEGIN{printf "%.2f", (b>0 ? a/b : 0)}'))"
        echo "$name-$d $ratio $(awk -v a="$iff" -v b="$ic" 'BEGIN{printf "%.3f", (b>0 ? a/b : 0)}')" >>"$plotdata"
      else
        echo "$name-$d $ratio NaN" >>"$plotdata"
      fi
      read -r wms wmf <<<"$wrow"
      echo "| $name | $what | $d | $(r4 "$c") | $(r4 "$worst") ($ratio) | $(r4 "$med") | ${wms:-} | ${wmf:-} | $icpc | $icpf |"
    done
  done
} >"$results/robustness$suffix.md"

# The peer's bars only where it ran (ICP=0 leaves them all NaN, and gnuplot refuses a series without a point).
plot_cmd="plot '$plotdata' using 2:xtic(1) title 'pmslam' lc rgb '#1f77b4'"
awk '$3 != "NaN" {found=1} END {exit !found}' "$plotdata" &&
  plot_cmd="$plot_cmd, '' using 3 title 'MRPT ICP-SLAM (tuned)' lc rgb '#d62728'"
gnuplot <<EOF || note "plot failed"
set terminal pngcairo size 1200,600 font "Sans,9" noenhanced
set output '$results/robustness$suffix.png'
set title "Error under injected faults / clean error (worst seed; 1 = unaffected; log scale)"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8
set logscale y
set yrange [0.5:*]
set ylabel 'error / clean error'
set xtics rotate by -60 scale 0
set grid ytics
$plot_cmd
EOF
note "wrote $results/robustness$suffix.md and robustness$suffix.png"
exit $failed

#!/usr/bin/env bash
# A/B comparison of two pm-slam-app builds on everything a behaviour change must be judged on together: the clean
# logs (5 runs each, sigma x 0.998 ... 1.002, medians) and the whole fault benchmark (every fault of
# bench/faults.txt at the given levels, every seed). One run is one sample; a change is decided on these medians and
# on the worst seeds of every row, never on one log's gain.
#
#   bench/compare.sh BIN_A BIN_B [DATASETS_DIR]      e.g. bench/compare.sh /tmp/pm-slam-app-main build/bin/pm-slam-app
#
# BIN_A, BIN_B: two pm-slam-app executables (copy one away before rebuilding the other). Both run with
# config/default.ini and the same options as bench/robustness.sh. DATASETS_DIR: default ../shared/datasets.
# Environment: SEEDS (default "1 2 3 4 5"), LEVELS (default "a b c"), FAULTS (names, default all), LOGS (default
# "intel aces fr079"), JOBS (runs side by side, default 2), ENV_A / ENV_B ("NAME=VALUE ..." set for that binary
# only), CLEAN=0 to skip the clean runs, SIDES ("a": run build A only, keeping its runs; "b": run build B only and
# compare it with the build/compare/a.txt an earlier call left, which must hold the same runs; default "a b"),
# RUN_LIMIT (seconds one run may take before it is stopped and counted as failed, default 900: a build whose search
# runs away on one log must not hold up the comparison of the other 284 runs).
# Writes build/compare/{a,b}/<run>/ (outputs) and build/compare/{a,b}.txt ("<run> <error m>" per line), and
# prints: clean medians A -> B; per fault x log row worst and median A -> B where either crosses 1.15 x clean + 2 mm
# or they differ by more than 2 mm; the number of runs over that line and the sums of errors. The faulted logs are
# generated once into build/compare/logs/ and kept (pm-fault-inject is deterministic per seed).
# Exit status: 0 done, 1 a run failed (listed), 2 bad input.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
die() { echo "bench/compare.sh: $*" >&2; exit 2; }
note() { echo "[compare] $*" >&2; }
[ $# -ge 2 ] && [ $# -le 3 ] || die "usage: bench/compare.sh BIN_A BIN_B [DATASETS_DIR]"
bin_a="$(realpath "$1")"; bin_b="$(realpath "$2")"
for b in "$bin_a" "$bin_b"; do [ -x "$b" ] || die "'$b': not an executable"; done
datasets="${3:-$repo/../shared/datasets}"
[ -d "$datasets" ] || die "datasets folder '$datasets' not found (give it as the third argument)"
datasets="$(cd "$datasets" && pwd)"
seeds="${SEEDS:-1 2 3 4 5}"; levels="${LEVELS:-a b c}"; logs="${LOGS:-intel aces fr079}"; jobs="${JOBS:-2}"
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || die "JOBS='$jobs': expected a whole number"
run_limit="${RUN_LIMIT:-900}"
[[ "$run_limit" =~ ^[1-9][0-9]*$ ]] || die "RUN_LIMIT='$run_limit': expected a whole number of seconds"
build="$repo/build"; work="$build/compare"; tools="$build/bin"
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target pm-fault-inject pm-slam-eval >/dev/null
mkdir -p "$work/logs"
config="$work/default.ini"
cp "$repo/config/default.ini" "$config"
sigma=$(awk -F= '/^\[/{s=$0} s=="[PerfectMatch]" && $1~/^ *sigma *$/ {gsub(/ /,"",$2); print $2}' "$config")
[ -n "$sigma" ] || die "config/default.ini has no [PerfectMatch] sigma"

# The runs: "<name>|<log file>|<dataset>|<extra pm-slam-app option or ->" per line.
runs="$work/runs.txt"; : >"$runs"
for d in $logs; do
  [ -f "$datasets/$d/$d.clf" ] && [ -f "$datasets/$d/$d.relations" ] || die "$datasets/$d/$d.clf or .relations missing"
  if [ "${CLEAN:-1}" != 0 ]; then
    for f in 0.998 0.999 1 1.001 1.002; do
      echo "clean-$d-$f|$datasets/$d/$d.clf|$d|PerfectMatch.sigma=$(awk -v a="$sigma" -v b="$f" 'BEGIN {printf "%.6g", a * b}')" >>"$runs"
    done
  fi
  while IFS='|' read -r name fargs _; do
    [[ -z "$name" || "$name" == \#* ]] && continue
    level="${name##*-}"
    [[ " $levels " == *" $level "* ]] || continue
    [ -z "${FAULTS:-}" ] || [[ " $FAULTS " == *" $name "* ]] || continue
    for s in $seeds; do
      log="$work/logs/$name-$d-$s.clf"
      # shellcheck disable=SC2086
      [ -s "$log" ] || "$tools/pm-fault-inject" $fargs --seed "$s" "$datasets/$d/$d.clf" "$log" 2>/dev/null \
        || die "pm-fault-inject $fargs --seed $s failed"
      echo "$name-$d-$s|$log|$d|-" >>"$runs"
    done
  done <"$repo/bench/faults.txt"
done
note "$(wc -l <"$runs") runs per build, $jobs at a time"

# one SIDE BIN ENV LINE: a run and its error (nan when it failed)
one() {
  local side=$1 bin=$2 envs=$3 name log d opt out err
  IFS="|" read -r name log d opt <<<"$4"
  out="$work/$side/$name"; mkdir -p "$out"
  local opts=(); [ "$opt" = - ] || opts=(--set "$opt")
  # shellcheck disable=SC2086
  if timeout "$run_limit" env $envs "$bin" --config "$config" "${opts[@]}" --no-progress --max-untracked 1e9 "$log" --out "$out" \
       >"$out/stdout.txt" 2>"$out/stderr.txt" &&
     "$tools/pm-slam-eval" --json "$out/trajectory.txt" "$datasets/$d/$d.relations" >"$out/eval.json" 2>/dev/null; then
    err=$(tr ',{}' '\n\n\n' <"$out/eval.json" | awk -F: '/"trans_mean_m"/ {gsub(/ /,"",$2); print $2}')
  else
    err=nan
  fi
  rm -f "$out"/map.* "$out/graph.graph"
  echo "$name $err"
}
export -f one
export work config datasets tools run_limit
sides="${SIDES:-a b}"
for s in $sides; do [[ "$s" == a || "$s" == b ]] || die "SIDES='$sides': expected a, b or \"a b\""; done
[ -n "${sides// /}" ] || die "SIDES is empty: expected a, b or \"a b\""
# Build A not run now is compared as an earlier call left it: only if that call ran exactly these runs.
[[ " $sides " == *" a "* ]] || cmp -s <(cut -d' ' -f1 "$work/a.txt" 2>/dev/null) <(cut -d'|' -f1 "$runs" | sort) ||
  die "SIDES='$sides': $work/a.txt is missing or holds other runs than these SEEDS, LEVELS, FAULTS and LOGS"
for side in $sides; do
  if [ $side = a ]; then bin=$bin_a; envs="${ENV_A:-}"; else bin=$bin_b; envs="${ENV_B:-}"; fi
  note "build $side: $bin ${envs:+($envs)}"
  # xargs -d '\n' passes one line per call; the replacement string is one no line holds.
  xargs -d '\n' -P "$jobs" -I@LINE@ bash -c 'one "$0" "$1" "$2" "$3"' "$side" "$bin" "$envs" @LINE@ <"$runs" \
    | sort >"$work/$side.txt"
done

if [[ " $sides " != *" b "* ]]; then note "build A's runs are in $work/a.txt: compare a build with them by SIDES=b"; exit 0; fi

# --- comparison ---------------------------------------------------------------------------------------------------
awk '
  function med(list,   n, v, i, j, t) { n = split(list, v, " "); for (i = 1; i <= n; i++) for (j = i + 1; j <= n; j++) if (v[j] + 0 < v[i] + 0) { t = v[i]; v[i] = v[j]; v[j] = t }
                                         return n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2 }
  function worst(list,   n, v, i, w) { n = split(list, v, " "); w = v[1]; for (i = 2; i <= n && w != "nan"; i++) if (v[i] == "nan" || v[i] + 0 > w + 0) w = v[i]; return w }
  FNR == 1 { side++ }
  { name = $1; err = $2; if (err == "nan") failed[side " " name] = 1
    n = split(name, p, "-")
    if (p[1] == "clean") { row = "clean " p[2] } else { row = p[1] "-" p[2] " " p[3] }
    errs[side, row] = errs[side, row] " " err; rows[row] = 1
    if (err != "nan" && p[1] != "clean") sum[side] += err }
  END {
    for (r in rows) if (r ~ /^clean /) { split(r, q, " "); clean[q[2]] = med(errs[1, r]) }
    printf "clean logs, 5-run medians (m):"; for (d in clean) printf "  %s %.4f -> %.4f", d, clean[d], med(errs[2, "clean " d])
    printf "%s\n", length(clean) ? "" : " not run (CLEAN=0): no row is held against 1.15 x clean + 2 mm"
    printf "%-16s %-6s %-24s %-24s\n", "fault", "log", "worst A -> B", "median A -> B"
    for (r in rows) { if (r ~ /^clean /) continue; split(r, q, " "); lim = (q[2] in clean) ? 1.15 * clean[q[2]] + 0.002 : 1e9
      wa = worst(errs[1, r]); wb = worst(errs[2, r]); ma = med(errs[1, r]); mb = med(errs[2, r])
      na = split(errs[1, r], va, " "); nb = split(errs[2, r], vb, " ")
      for (i = 1; i <= na; i++) over[1] += (va[i] == "nan" || va[i] > lim); for (i = 1; i <= nb; i++) over[2] += (vb[i] == "nan" || vb[i] > lim)
      total += na
      if (wa == "nan" || wb == "nan" || wa > lim || wb > lim || wa - wb > 0.002 || wb - wa > 0.002)
        printf "%-16s %-6s %-24s %-24s\n", q[1], q[2], sprintf("%.4f -> %.4f", wa, wb), sprintf("%.4f -> %.4f", ma, mb) | "sort"
    }
    close("sort")
    printf "faulted runs over 1.15 x clean + 2 mm: %d -> %d of %d; sum of their errors %.3f -> %.3f m\n", over[1], over[2], total, sum[1], sum[2]
    for (f in failed) { split(f, q, " "); printf "FAILED: build %s, run %s (see build/compare/%s/%s/)\n", q[1] == 1 ? "a" : "b", q[2], q[1] == 1 ? "a" : "b", q[2]; bad = 1 }
    exit bad
  }' "$work/a.txt" "$work/b.txt"

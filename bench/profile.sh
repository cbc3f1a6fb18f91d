#!/usr/bin/env bash
# Where pmslam's time goes: a sampling profile (Linux perf) of one pm-slam-app run, split into the front-end (the
# main thread: reading the log, matching, inserting, writing the outputs) and the loop-closure back-end (its
# worker threads), the hottest functions of each.
#
#   bench/profile.sh LOG [pm-slam-app options...]      e.g. bench/profile.sh ../shared/datasets/intel/intel.clf
#
# Environment: FREQ=N samples per second (default 2000), TOP=N functions listed per part (default 20).
# Needs `perf` (Debian: linux-perf) and permission to sample (as root, or kernel.perf_event_paranoid <= 1).
# Writes build/profile/<log>.txt (the table, also printed) and build/profile/<log>.data (perf's samples, for
# `perf report -i`). Exit status: 0 done, 1 the run or perf failed, 2 bad input.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$repo/build"
freq="${FREQ:-2000}"
top="${TOP:-20}"
die() { echo "bench/profile.sh: $*" >&2; exit 2; }
[ $# -ge 1 ] || die "usage: bench/profile.sh LOG [pm-slam-app options...]"
log="$1"; shift
[ -f "$log" ] || die "'$log': no such log file"
command -v perf >/dev/null || die "'perf' is not installed (Debian package linux-perf)"
[[ "$freq" =~ ^[1-9][0-9]*$ ]] || die "FREQ='$freq': expected a whole number"
[[ "$top" =~ ^[1-9][0-9]*$ ]] || die "TOP='$top': expected a whole number"

cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j2 --target pm-slam-app >/dev/null
name="$(basename "${log%.*}")"
out="$build/profile"; mkdir -p "$out/$name-run"
data="$out/$name.data"
echo "[profile] $name: pm-slam-app under perf record -F $freq ..." >&2
perf record -q -o "$data" -F "$freq" -- "$build/bin/pm-slam-app" --no-progress "$@" "$log" --out "$out/$name-run" \
  >"$out/$name-run/stdout.txt" 2>&1 || { tail -n 5 "$out/$name-run/stdout.txt" >&2; exit 1; }

# Samples by thread (perf script names a sample's symbol only when its address is asked for too): the first
# thread seen is the main one (the front-end); every other is the back-end (a worker
# per loop-closure job). Symbols lose their argument lists, so template instances of one function add up.
perf script -i "$data" -F tid,ip,sym 2>/dev/null | awk -v top="$top" -v total_hz="$freq" '
  NF < 2 { next }
  { tid = $1; $1 = ""; $2 = ""; sym = substr($0, 3); gsub(/\(anonymous namespace\)/, "{anon}", sym); sub(/\(.*/, "", sym); if (sym == "") sym = "[unknown]"
    if (main == "") main = tid
    part = (tid == main) ? "front-end (main thread)" : "back-end (loop-closure workers)"
    n[part]++; c[part SUBSEP sym]++; all++ }
  END {
    for (p in n) {
      printf "== %s: %d samples, %.1f %% of all, %.2f s of CPU\n", p, n[p], 100 * n[p] / all, n[p] / total_hz
      k = 0
      for (key in c) { split(key, a, SUBSEP); if (a[1] == p) { s[++k] = sprintf("%09d %s", c[key], a[2]) } }
      m = k; for (i = 1; i <= m; i++) for (j = i + 1; j <= m; j++) if (s[j] > s[i]) { t = s[i]; s[i] = s[j]; s[j] = t }
      for (i = 1; i <= m && i <= top; i++) { cnt = substr(s[i], 1, 9) + 0; printf "  %5.1f %%  %s\n", 100 * cnt / all, substr(s[i], 11) }
      delete s
    }
  }' | tee "$out/$name.txt"
grep -E "time per scan|SLAM time" "$out/$name-run/stdout.txt" | sed 's/^ */  /' | tee -a "$out/$name.txt"

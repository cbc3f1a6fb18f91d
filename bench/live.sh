#!/usr/bin/env bash
# Live mode on emulated sensors: pm-slam-app --live with MRPT's real drivers (CHokuyoURG over Ethernet, CLMS100Eth)
# against the lidar emulator of the tests (tests/support/lidar_emulator: scans ray-cast in a 20 m x 12 m loop of
# corridors, served in real time along a known path at 0.5 m/s), then MRPT's ICP-SLAM (pm-icp-slam, the peer) on
# the recording of the same run.
#
#   bench/live.sh [SECONDS]     (default 120: a lap of the loop and a bit; the SICK runs 15 s longer, its driver's start-up)
#
# Reports per sensor: scans received / processed / dropped, the latency from a scan's timestamp to its pose (p50, p99,
# max), ms/scan (mean, median, p99), peak RSS, and the error against the emulator's truth (relations 1 s apart,
# bench/live_truth.py); the same for pm-icp-slam on the recording, and the ratios. Writes bench/results/live.md.
# Exit status: 0 done, 1 a run failed, 2 bad input.
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-120}"
build="$repo/build"
bin="$build/bin"
work="$build/bench-runs/live"
results="$repo/bench/results"

die() { echo "bench/live.sh: $*" >&2; exit 2; }
note() { echo "[live] $*" >&2; }
[ $# -le 1 ] || die "usage: bench/live.sh [SECONDS]"
[[ "$seconds" =~ ^[0-9]+$ ]] || die "SECONDS must be a whole number, got '$seconds'"
for tool in cmake python3 timeout awk; do command -v "$tool" >/dev/null || die "'$tool' is not installed"; done

note "building Release in $build"
mkdir -p "$build"
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release >"$build/live-build.log" 2>&1 || die "cmake failed ($build/live-build.log)"
cmake --build "$build" -j2 --target pm-slam-app pmslam-sensors pm-lidar-emulator pm-icp-slam >>"$build/live-build.log" 2>&1 \
  || die "build failed ($build/live-build.log)"
rm -rf "$work"
mkdir -p "$work" "$results"

field() {  # field FILE REGEX: the first match's first group (sed -E)
  sed -nE "s/$2/\1/p" "$1" | head -1
}

rows=""
for sensor in hokuyo sick; do
  dir="$work/$sensor"
  mkdir -p "$dir"
  if [ "$sensor" = hokuyo ]; then protocol=scip; duration=$seconds; else protocol=lms1xx; duration=$((seconds + 15)); fi
  "$bin/pm-lidar-emulator" --protocol "$protocol" --truth "$dir/truth.txt" >"$dir/emulator.out" 2>&1 &
  emulator=$!
  port=""
  for _ in $(seq 100); do
    port=$(awk '/^PORT/{print $2}' "$dir/emulator.out")
    [ -n "$port" ] && break
    sleep 0.05
  done
  [ -n "$port" ] || { kill "$emulator"; die "the emulator did not start ($dir/emulator.out)"; }
  if [ "$sensor" = hokuyo ]; then
    printf '[LIDAR]\ndriver = CHokuyoURG\nprocess_rate = 90\nIP_DIR = 127.0.0.1\nPORT_DIR = %s\n' "$port" >"$dir/sensors.ini"
  else
    printf '[LIDAR]\ndriver = CLMS100Eth\nprocess_rate = 50\nip_address = 127.0.0.1\nTCP_port = %s\n' "$port" >"$dir/sensors.ini"
  fi
  note "$sensor: pm-slam-app --live for $duration s"
  status=0
  timeout -s INT -k 60 --preserve-status "$duration" "$bin/pm-slam-app" --live "$dir/sensors.ini" --out "$dir/out" \
    --record "$dir/live.rawlog" --no-progress >"$dir/pmslam.log" 2>&1 || status=$?
  kill "$emulator" 2>/dev/null || true
  wait "$emulator" 2>/dev/null || true
  [ "$status" = 0 ] || { echo "bench/live.sh: pm-slam-app --live failed ($status): $dir/pmslam.log" >&2; exit 1; }
  note "$sensor: pm-icp-slam on the recording"
  "$bin/pm-icp-slam" --config "$repo/config/icp-slam-tuned.ini" --out "$dir/icp" "$dir/live.rawlog" >"$dir/icp.log" 2>&1 \
    || { echo "bench/live.sh: pm-icp-slam failed: $dir/icp.log" >&2; exit 1; }

  log="$dir/pmslam.log"
  received=$(field "$log" '.*live: [0-9]+ objects received \(([0-9]+) scans\).*')
  dropped=$(field "$log" '.* ([0-9]+) dropped because.*')
  lat=$(field "$log" '.*to its pose: p50 ([0-9.]+ ms, p99 [0-9.]+ ms, max [0-9.]+) ms.*' | sed 's/ ms, p99 / \/ /; s/ ms, max / \/ /')
  ms=$(field "$log" '.*time per scan \(match \+ map update\): mean ([0-9.]+ ms, median [0-9.]+ ms, p99 [0-9.]+) ms.*' | sed 's/ ms, median / \/ /; s/ ms, p99 / \/ /')
  mean=$(field "$log" '.*time per scan \(match \+ map update\): mean ([0-9.]+) ms.*')
  rss=$(field "$log" '.*peak memory ([0-9.]+) MB.*')
  loops=$(field "$log" '.*loop closure: ([0-9]+) loops closed.*')
  read -r poses terr tmax rerr drift < <(python3 "$repo/bench/live_truth.py" "$dir/truth.txt" "$dir/out/trajectory.txt")
  ilog="$dir/icp.log"
  ims=$(field "$ilog" '.*time per scan \(ICP \+ map update\): mean ([0-9.]+ ms, median [0-9.]+ ms, p99 [0-9.]+) ms.*' | sed 's/ ms, median / \/ /; s/ ms, p99 / \/ /')
  imean=$(field "$ilog" '.*time per scan \(ICP \+ map update\): mean ([0-9.]+) ms.*')
  irss=$(field "$ilog" '.*peak memory ([0-9.]+) MB.*')
  read -r _ iterr itmax irerr idrift < <(python3 "$repo/bench/live_truth.py" "$dir/truth.txt" "$dir/icp/trajectory.txt")
  ratio=$(awk -v a="$imean" -v b="$mean" 'BEGIN{printf "%.1f", a / b}')
  rows+="| $sensor | pm-slam-app --live | $received / $poses / $dropped | $lat | $ms | $rss | $terr / $tmax | $rerr | $drift | $loops |"$'\n'
  rows+="| $sensor | pm-icp-slam on the recording | $poses | – | $ims (${ratio}× pm-slam-app) | $irss | $iterr / $itmax | $irerr | $idrift | – |"$'\n'
done

{
  echo "# Live mode on emulated sensors (bench/live.sh $seconds)"
  echo
  echo "MRPT's real drivers against tests/support/lidar_emulator on localhost, $(date -u +%Y-%m-%d), $(git -C "$repo" rev-parse --short HEAD)."
  echo "Error against the emulator's truth: relations 1 s apart (mean / max, m; rotation mean, deg) and the largest"
  echo "drift from the first pose (m). Latency: from a scan's timestamp (the driver's) to its pose."
  echo
  echo "| sensor | run | scans received / processed / dropped | latency p50 / p99 / max (ms) | ms/scan mean / median / p99 | peak RSS (MB) | trans. error mean / max (m) | rot. error (deg) | drift (m) | loops closed |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  printf '%s' "$rows"
} >"$results/live.md"
cat "$results/live.md"

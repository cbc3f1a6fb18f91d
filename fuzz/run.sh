#!/usr/bin/env bash
# Build the libFuzzer targets with clang (-fsanitize=fuzzer,address,undefined) in build-fuzz/ and
# run each for SECONDS (default 30) on a copy of its seed corpus (fuzz/corpus/<target>/ is never
# modified). Exits non-zero on any crash, sanitizer report, leak, timeout or out-of-memory, in
# pmslam or in MRPT code it calls; the input that did it is kept in build-fuzz/artifacts/.
#   fuzz/run.sh [SECONDS]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-30}"
case "$seconds" in '' | *[!0-9]*) echo "usage: fuzz/run.sh [SECONDS]" >&2; exit 2 ;; esac
build="$here/build-fuzz"
targets=(fuzz_carmen_line fuzz_rawlog fuzz_ini)

# clang and its libFuzzer runtime (Debian 12: clang 14), besides what scripts/setup.sh installs.
packages=(clang libclang-rt-14-dev cmake libmrpt-dev libmrpt-graphslam-dev libmrpt-hwdrivers-dev libceres-dev libpng-dev zlib1g-dev libeigen3-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "pmslam fuzz: installing missing packages: ${missing[*]}" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  "${sudo_cmd[@]}" apt-get update -q
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

jobs="$(nproc 2>/dev/null || echo 2)"
CC=clang CXX=clang++ cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPMSLAM_FUZZ=ON \
  -DPMSLAM_BUILD_TESTS=OFF -DPMSLAM_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j"$jobs" --target "${targets[@]}"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$build/artifacts"
# Huge allocations requested by damaged input must fail (std::bad_alloc, caught by the
# readers) rather than abort: allocator_may_return_null. MRPT's singletons are not freed at exit.
export ASAN_OPTIONS="allocator_may_return_null=1:max_allocation_size_mb=1024:detect_leaks=1:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:${UBSAN_OPTIONS:-}"
status=0
for t in "${targets[@]}"; do
  mkdir -p "$work/$t"
  cp -R "$here/fuzz/corpus/$t/." "$work/$t/"
  dict=()
  if [ -f "$here/fuzz/$t.dict" ]; then dict=(-dict="$here/fuzz/$t.dict"); fi
  echo "pmslam fuzz: $t for ${seconds} s ($(ls "$work/$t" | wc -l) seed inputs)"
  # A fixed seed keeps a run repeatable for the same binary and corpus (CI must not flip on luck).
  if "$build/bin/$t" -seed=1 -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2560 -malloc_limit_mb=2048 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/artifacts/$t-" "${dict[@]}" \
      "$work/$t" >"$work/$t.log" 2>&1; then
    grep -E "^stat::number_of_executed_units|^stat::average_exec_per_sec|^stat::peak_rss_mb" "$work/$t.log" |
      tr '\n' ' ' | sed 's/^/  /'
    echo
  else
    tail -n 80 "$work/$t.log" >&2
    echo "pmslam fuzz: $t FAILED; the input is in $build/artifacts/ (reproduce: $build/bin/$t FILE)" >&2
    status=1
  fi
done
exit "$status"

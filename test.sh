#!/usr/bin/env bash
# Install what is missing, build, and run the whole GoogleTest suite through ctest.
# --sanitize builds a separate tree (build-asan/) with AddressSanitizer + UBSan and runs the suite there.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build_dir="$here/build"; extra=()
if [ "${1:-}" = "--sanitize" ]; then
  build_dir="$here/build-asan"; extra=(-DPMSLAM_SANITIZE=ON -DPMSLAM_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo)
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
fi
"$here/scripts/setup.sh" "$build_dir" "${extra[@]}"
cd "$build_dir"
ctest --output-on-failure -j"$(nproc 2>/dev/null || echo 2)"

#!/usr/bin/env bash
# Shared by run.sh and test.sh: install what is missing (Debian 12, as root), then configure and build.
# Usage: scripts/setup.sh BUILD_DIR [extra cmake args...]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${1:-$here/build}"; shift || true

packages=(build-essential cmake libmrpt-dev libmrpt-graphslam-dev libmrpt-hwdrivers-dev libceres-dev libpng-dev zlib1g-dev libbz2-dev mrpt-apps mrpt-common libeigen3-dev libgtest-dev googletest libbenchmark-dev gnuplot-nox
          xvfb xauth xdotool)  # the last three: the --gui test in a virtual X server
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "pmslam: installing missing packages: ${missing[*]}" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  "${sudo_cmd[@]}" apt-get update -q
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S "$here" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build_dir" -j"$jobs"

#!/usr/bin/env bash
# Install what is missing, build, and run pm-slam-app. With no argument it maps the sample log that MRPT ships.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$here/scripts/setup.sh" "$here/build"
exec "$here/build/bin/pm-slam-app" "$@"

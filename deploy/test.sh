#!/usr/bin/env bash
# The second command: install what is missing, build, run every test.
# The exit status is ctest's verdict.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/deploy/build.sh"
cd "$root/build"
exec ctest -j "$(nproc)" --output-on-failure "$@"

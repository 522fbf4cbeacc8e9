#!/usr/bin/env bash
# The first command: install what is missing, build, run the default
# deployment, and say where its outputs are.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/deploy/build.sh"
cd "$root"
exec build/bin/hcosim up deploy/default.yaml --out out "$@"

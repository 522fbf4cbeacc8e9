#!/usr/bin/env bash
# The first command: install what is missing, build, run a deployment
# (deploy/default.yaml unless a FILE.yaml comes first), and say where its
# outputs are. A deployment with a security section gets a test CA and
# credentials the first time (hcosim security init, docs/security.md).
# Other arguments go to hcosim up.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
file=$root/deploy/default.yaml
if [[ "${1:-}" == *.yaml ]]; then
  file=$(realpath "$1")
  shift
fi
"$root/deploy/build.sh"
cd "$root"
if grep -q '^security:' "$file"; then
  build/bin/hcosim security init --deployment "$file" --keep
fi
exec build/bin/hcosim up "$file" --out out "$@"

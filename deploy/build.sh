#!/usr/bin/env bash
# Installs what is missing and builds hcosim (Release) into build/.
# Used by run.sh and test.sh; safe to run again (incremental, ccache).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/deploy/setup.sh"
cmake -S "$root" -B "$root/build" -G Ninja -DCMAKE_BUILD_TYPE=Release > "$root/build.log" 2>&1 ||
  { tail -n 30 "$root/build.log"; echo "hcosim: cmake failed, see build.log" >&2; exit 1; }
echo "hcosim: building (log: build.log)"
cmake --build "$root/build" -j "$(nproc)" >> "$root/build.log" 2>&1 ||
  { grep -E "error|FAILED" "$root/build.log" | head -n 30; echo "hcosim: build failed, see build.log" >&2; exit 1; }

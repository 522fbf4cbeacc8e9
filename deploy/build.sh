#!/usr/bin/env bash
# Installs what is missing and builds hcosim (Release) into build/.
# --sanitize: the same tree with AddressSanitizer and UndefinedBehaviorSanitizer
# (RelWithDebInfo, clang, libFuzzer coverage and fuzz targets) into
# build-asan/ instead.
# Used by run.sh and test.sh; safe to run again (incremental, ccache).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
name=build
args=(-DCMAKE_BUILD_TYPE=Release)
if [ "${1:-}" = "--sanitize" ]; then
  name=build-asan
  # Line tables only: the sanitizers' stack traces need file:line, and
  # full debug information made the build and its links slower.
  args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo -DHCOSIM_SANITIZE=address,undefined -DHCOSIM_FUZZ=ON
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG"
    "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG")
  export CC=clang CXX=clang++
  # A build-asan/ configured with gcc (before clang) cannot switch compiler.
  if [ -f "$root/$name/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang' "$root/$name/CMakeCache.txt"; then
    rm -rf "${root:?}/$name"
  fi
fi
log="$root/$name.log"
"$root/deploy/setup.sh"
cmake -S "$root" -B "$root/$name" -G Ninja "${args[@]}" > "$log" 2>&1 ||
  { tail -n 30 "$log"; echo "hcosim: cmake failed, see $name.log" >&2; exit 1; }
echo "hcosim: building $name/ (log: $name.log)"
cmake --build "$root/$name" -j "$(nproc)" >> "$log" 2>&1 ||
  { grep -E "error|FAILED" "$log" | head -n 30; echo "hcosim: build failed, see $name.log" >&2; exit 1; }

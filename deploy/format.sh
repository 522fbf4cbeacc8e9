#!/usr/bin/env bash
# Checks that every C and C++ file in git follows .clang-format (clang-format-14,
# the version Debian 12 ships; another version formats some lines otherwise).
# --fix: formats them in place instead. Exit 1 names each file that is off.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
"$root/deploy/setup.sh"
mapfile -t files < <(git ls-files '*.c' '*.cc' '*.h')
if [ "${1:-}" = "--fix" ]; then
  clang-format-14 -i "${files[@]}"
  exit 0
fi
# One run over all files; its warnings begin with the file's name.
mapfile -t off < <(clang-format-14 --dry-run "${files[@]}" 2>&1 | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: warning:.*/\1/p' | sort -u)
if ((${#off[@]})); then
  printf 'hcosim format: %s is not formatted (deploy/format.sh --fix)\n' "${off[@]}" >&2
  exit 1
fi
echo "hcosim format: ${#files[@]} files follow .clang-format"

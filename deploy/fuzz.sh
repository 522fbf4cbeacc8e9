#!/usr/bin/env bash
# Runs each libFuzzer target (tests/fuzz/, built in build-asan/ by
# ./deploy/build.sh --sanitize: clang, AddressSanitizer and
# UndefinedBehaviorSanitizer) for SECONDS (default 30) on a copy of its seed
# corpus. An input that crashes, hangs (over 10 s) or allocates over 1 GiB
# is kept in build-asan/fuzz/NAME/: copy it into tests/fuzz/regressions/NAME/
# and ctest replays it from then on (fuzz.replay_NAME).
# Usage: deploy/fuzz.sh [SECONDS] [NAME...]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-30}
[ $# -gt 0 ] && shift
names=("$@")
[ ${#names[@]} -eq 0 ] && names=(deployment script obj intrinsics recording sample)
"$root/deploy/build.sh" --sanitize
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:new_delete_type_mismatch=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export OPENCV_VIDEOIO_PRIORITY_GPHOTO2=0
failed=()
for name in "${names[@]}"; do
  work="$root/build-asan/fuzz/$name"
  rm -rf "$work" && mkdir -p "$work/corpus"
  cp -r "$root/tests/fuzz/corpus/$name/." "$work/corpus/"
  echo "fuzz: $name for $seconds s"
  if ! "$root/build-asan/tests/bin/fuzz_$name" "$work/corpus" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -malloc_limit_mb=1024 -artifact_prefix="$work/" -print_final_stats=1 >"$work/log" 2>&1; then
    failed+=("$name")
    grep -E "ERROR|SUMMARY|Test unit written" "$work/log" | head -n 20
  fi
  echo "fuzz: $name: $(grep -E '^stat::number_of_executed_units' "$work/log" | awk '{print $2}') inputs," \
    "$(grep -E '^stat::peak_rss_mb' "$work/log" | awk '{print $2}') MB peak, corpus $(ls "$work/corpus" | wc -l) files"
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}: the inputs are in build-asan/fuzz/NAME/ (crash-*, timeout-*, oom-*)" >&2
  exit 1
fi
echo "fuzz: no finding in ${names[*]}"

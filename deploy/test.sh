#!/usr/bin/env bash
# The second command: install what is missing, build, run every test.
# The exit status is ctest's verdict. Extra arguments go to ctest.
# --sanitize (first): the same in build-asan/, under AddressSanitizer and
# UndefinedBehaviorSanitizer; any finding fails its test. That run leaves
# out the tests labelled (tests/CMakeLists.txt):
#   bench     a benchmark's frame: a suite run briefly to check its rows;
#   realtime  asserts a rate or a count of samples in wall time, which the
#             sanitizers' slowdown changes;
#   slow      minutes under the sanitizers; a shorter test runs its code there
#             (a GoogleTest suite named ...Slow, or instantiated as Slow/).
set -euo pipefail
# run_ctest ARGS...: ctest, then each failed test's own failure lines again
# at the end, where a CI log's tail shows them.
run_ctest() {
  local rc=0
  ctest -j "$(nproc)" --output-on-failure "$@" || rc=$?
  if [ "$rc" -ne 0 ] && [ -f Testing/Temporary/LastTest.log ]; then
    echo "--- why each failed test failed (Testing/Temporary/LastTest.log):"
    awk '/^[0-9]+\/[0-9]+ Testing: /{name=$3; n=0; out=0; next}
         /^Output:$/{out=1; next}
         /^<end of output>$/{out=0; next}
         out && /FAIL|Failure|Expected|Which is|error|Error|Sanitizer/ && n<12 {lines[n++]=$0}
         /^Test Failed\.$/{print name ":"; for (i=0; i<n; i++) print "  " lines[i]}' \
      Testing/Temporary/LastTest.log
  fi
  return "$rc"
}
root=$(cd "$(dirname "$0")/.." && pwd)
if [ "${1:-}" = "--sanitize" ]; then
  shift
  "$root/deploy/build.sh" --sanitize
  cd "$root/build-asan"
  # new_delete_type_mismatch=0: Fast DDS 2.9.1 itself deletes its
  # statistics writer (88 bytes) through an RTPSWriter pointer (56) in
  # RTPSWriter::~RTPSWriter, on every writer's deletion; nothing of ours.
  export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:new_delete_type_mismatch=0"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
  # Leaks in third-party libraries only, each explained in the file.
  export LSAN_OPTIONS="suppressions=$root/deploy/lsan.supp"
  run_ctest -LE '^(bench|realtime|slow)$' "$@"
  exit
fi
"$root/deploy/build.sh"
cd "$root/build"
run_ctest "$@"

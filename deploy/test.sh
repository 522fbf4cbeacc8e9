#!/usr/bin/env bash
# The second command: install what is missing, build, run every test.
# The exit status is ctest's verdict. Extra arguments go to ctest.
# --sanitize (first): the same in build-asan/, under AddressSanitizer and
# UndefinedBehaviorSanitizer; any finding fails its test. Left out there:
# the benchmarks' frames and the real-time tests that assert a rate or a
# count of samples in wall time (a sanitizer slows every process several
# times); the lockstep tests run the same services and still run, with
# their hang limits 3 times longer (tests/CMakeLists.txt). Left out too:
# three long model sweeps (229, 127 and 77 s there, 8 s each in build/,
# at 51b3b36), whose code shorter tests run under the sanitizers as well:
# the S-Chain against the behaviour model at five depths
# (Hybrid.StifferSidePushesBackHarderInBothModels runs both models), a
# minute-long hybrid contact (Hybrid.ReleaseReturnsToTheRestShape,
# SChain.FarNanAndLongHeldContactsAreHandled), the adaptive model's
# activation spreading and retiring over up to 3 s for each integrator
# (MassspringAdaptive's three other tests), and the elastic surfaces'
# 2.7 s press and recovery for all but symplectic_euler (1.7 to 11 s each
# in build/, velocity_verlet 107 s in build-asan/, at d587c88;
# symplectic_euler, 54 s there, runs the same hinges and surfaces), and
# their stiff-hinge substep runs (0.6 to 3.2 s each in build/).
set -euo pipefail
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
  exec ctest -j "$(nproc)" --output-on-failure \
    -E '^(bench\..*|integration\.(haptic|haptic_loop|deformable|ar_view|tracker|replay|stall|faults|security_wire)|interop\.cyclone_mesh|Hybrid\.(ChainForceAgreesWithTheBehaviorModel|MinuteLongContactAtTheCentreStaysFinite)|MassspringAdaptivePerIntegrator\.ActivationSpreadsFromTheContactAndRetires/.*|Integrators/ElasticSurfacePerIntegrator\.PressedAndReleasedItRecoversItsRestShape/(velocity_verlet|rk4|implicit_euler|local_global)|Integrators/ElasticSurfacePerIntegrator\.StiffHingesTakeTheirSubstepsAndStayStable/.*)$' "$@"
fi
"$root/deploy/build.sh"
cd "$root/build"
exec ctest -j "$(nproc)" --output-on-failure "$@"

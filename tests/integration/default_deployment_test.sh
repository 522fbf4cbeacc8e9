# deploy/default.yaml, what ./deploy/run.sh starts, runs to its end on its
# own domain: every service exits 0 and the haptic device ran its 2000 ticks.
source "$(dirname "$0")/lib.sh"
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cp -r "$ROOT/deploy/scripts" "$WORK/"
sed -E "s/^domain: .*/domain: $DOMAIN/" "$ROOT/deploy/default.yaml" >"$WORK/default.yaml"
grep -q "^domain: $DOMAIN$" "$WORK/default.yaml" || fail "default.yaml has no top-level domain line to override"
timeout 60 "$BIN/hcosim" up "$WORK/default.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?"
grep -q "lockstep run complete" "$WORK/up.log" || fail "the lockstep run did not complete"
[ "$(grep -c "exit status 0" "$WORK/up.log")" -eq "$(grep -c "started " "$WORK/up.log")" ] || fail "a service failed"
grep -q "omni: 2000 ticks" "$WORK/out/logs/omni.log" || fail "the haptic device did not run 2000 ticks"
echo "default_deployment_test: ok"

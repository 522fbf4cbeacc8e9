# A service that builds its model before its loop runs (here: waits 11 s)
# reports "starting" until then; up says so after 10 s, and a real-time
# duration counts from when every service runs, so it gets its whole 2 s.
# In lockstep the clock waits for it past its join limit.
source "$(dirname "$0")/lib.sh"
deployment slow.yaml <<'YAML'
mode: realtime
duration: 2
services:
  - {name: slow, kind: test_probe, rate: 100, params: {role: source, start_delay: 11}}
  - {name: quick, kind: test_probe, rate: 100, params: {role: wall}}
YAML
limit 60 "$BIN/hcosim" up "$WORK/slow.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1
code=$?
[ $code -eq 0 ] || fail "up exited $code"
grep -q "every service joined domain $DOMAIN" "$WORK/up.log" || fail "no join line"
grep -q "still starting after 10 s: slow$" "$WORK/up.log" || fail "up did not name the service still starting"
# Then where each participant listens: its GUID prefix and unicast locators.
for p in slow quick; do
  grep -qE "^hcosim up:   participant $p [0-9a-f.]+, discovery at .*:[0-9]+, data at .*:[0-9]+$" "$WORK/up.log" ||
    fail "up did not say where $p listens"
done
after=$(sed -nE 's/^hcosim up: every service running after ([0-9.]+) s$/\1/p' "$WORK/up.log")
[ -n "$after" ] || fail "no 'every service running' line"
awk -v t="$after" 'BEGIN { exit !(t >= 11 && t < 20) }' || fail "every service running after $after s, expected 11 to 20"
total=$(sed -nE 's/^hcosim up: duration reached after ([0-9.]+) s$/\1/p' "$WORK/up.log")
awk -v t="$total" -v a="$after" 'BEGIN { exit !(t >= a + 2 && t < a + 3) }' ||
  fail "the run ended after $total s; expected the 2 s duration from $after s"
# 2 s at 100 Hz is 200 steps; half that allows for a loaded machine.
steps=$(sed -nE 's/^probe slow: role source, steps ([0-9]+),.*/\1/p' "$WORK/out/logs/slow.log")
[ -n "$steps" ] && [ "$steps" -ge 100 ] || fail "slow ran ${steps:-no} steps, expected about 200"
grep -q "slow .*exit status 0" "$WORK/up.log" || fail "slow did not end cleanly: $(cat "$WORK/up.log")"

# Lockstep: the clock waits past its 30 s join limit for a follower that
# says it is starting (a large model, or any model under a sanitizer).
deployment slow_lockstep.yaml <<'YAML'
mode: lockstep
duration: 0.5
services:
  - {name: slow, kind: test_probe, rate: 100, params: {role: source, start_delay: 32}}
  - {name: quick, kind: test_probe, rate: 100, params: {role: wall}}
YAML
limit 90 "$BIN/hcosim" up "$WORK/slow_lockstep.yaml" --out "$WORK/ls" >"$WORK/ls.log" 2>&1 ||
  fail "lockstep up exited $?: $(cat "$WORK/ls.log")"
grep -q "lockstep run complete" "$WORK/ls.log" || fail "the lockstep run did not complete: $(cat "$WORK/ls.log")"
grep -q "^clock: 500 steps" "$WORK/ls/logs/clock.log" || fail "clock: $(cat "$WORK/ls/logs/clock.log")"
echo "startup_test: ok (running after $after s, ended after $total s, slow $steps steps; lockstep past a 32 s start)"

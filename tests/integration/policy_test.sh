# Per-service fault policies (on_failure) in real time. restart: a service
# that fails is started again, up to 3 times, its log kept across
# restarts, and a service killed with SIGKILL is restarted too; the run
# reaches its duration and exits 0. ignore: the failed service stays down,
# the others run to the duration, and the exit status is 1. In lockstep
# both policies are refused with the file and line. No process and no
# shared-memory segment of the run is left behind, the killed one's
# included (ctest runs this test alone, so /dev/shm holds only its own).
source "$(dirname "$0")/lib.sh"
shm_before=$(shm_segments)

deployment restart.yaml <<'YAML'
mode: realtime
duration: 6
services:
  - name: steady
    kind: test_probe
    rate: 100
    params: {role: source}
  - name: flaky
    kind: test_probe
    rate: 100
    on_failure: restart
    params: {role: wall, fail_after: 2}
YAML
"$BIN/hcosim" up "$WORK/restart.yaml" --out "$WORK/r" >"$WORK/restart.log" 2>&1 &
up=$!
PIDS+=($up)
# Timeline: flaky's first instance is killed at about 0.8 s, the next two
# fail 2 s after their start (about 2.9 and 5 s), the fourth runs from
# about 5 s to the end at 6 s: 3 restarts, a second from either edge.
for i in $(seq 50); do grep -q "started flaky" "$WORK/restart.log" && break; sleep 0.1; done
flaky=$(sed -nE 's/.*started +flaky +pid ([0-9]+).*/\1/p' "$WORK/restart.log")
[ -n "$flaky" ] || fail "flaky was not started: $(cat "$WORK/restart.log")"
sleep 0.8
kill -9 "$flaky"
wait $up
code=$?
[ $code -eq 0 ] || fail "up with restarts exited $code: $(cat "$WORK/restart.log")"
grep -q "service 'flaky' ended (killed by signal 9 (Killed)); restarting it (1 of 3)" "$WORK/restart.log" ||
  fail "the killed service was not restarted: $(cat "$WORK/restart.log")"
grep -q "service 'flaky' ended (exit status 3); restarting it (2 of 3)" "$WORK/restart.log" ||
  fail "the failed service was not restarted: $(cat "$WORK/restart.log")"
grep -q "duration reached" "$WORK/restart.log" || fail "the run did not reach its duration"
grep -qE "flaky +exit status 0, 3 restarts" "$WORK/restart.log" ||
  fail "the summary does not count the restarts: $(cat "$WORK/restart.log")"
[ "$(grep -c -- '--- hcosim up: ended' "$WORK/r/logs/flaky.log")" -ge 2 ] || fail "flaky's log was not kept across restarts"

# Restarts run out: fail_after 0.5 in 6 s fails more than 3 times.
sed -i 's/fail_after: 2}/fail_after: 0.5}/' "$WORK/restart.yaml"
limit 30 "$BIN/hcosim" up "$WORK/restart.yaml" --out "$WORK/r2" >"$WORK/restart2.log" 2>&1
code=$?
[ $code -eq 1 ] || fail "up whose restarts ran out exited $code"
grep -q "service 'flaky' ended (exit status 3) after 3 restarts" "$WORK/restart2.log" ||
  fail "the end of the restarts was not named: $(cat "$WORK/restart2.log")"

# The same deployment (flaky failing after 0.5 s), flaky ignored.
sed 's/duration: 6/duration: 3/; s/on_failure: restart/on_failure: ignore/' "$WORK/restart.yaml" >"$WORK/ignore.yaml"
limit 30 "$BIN/hcosim" up "$WORK/ignore.yaml" --out "$WORK/i" >"$WORK/ignore.log" 2>&1
code=$?
[ $code -eq 1 ] || fail "up with an ignored failure exited $code, expected 1"
grep -q "service 'flaky' ended (exit status 3); on_failure: ignore, the others run on" "$WORK/ignore.log" ||
  fail "the ignored failure was not named: $(cat "$WORK/ignore.log")"
grep -q "duration reached" "$WORK/ignore.log" || fail "the others did not run to the duration"
grep -qE "steady +exit status 0" "$WORK/ignore.log" || fail "steady did not run on: $(cat "$WORK/ignore.log")"

# Lockstep refuses both, from the file and from --mode.
sed 's/mode: realtime/mode: lockstep/' "$WORK/ignore.yaml" >"$WORK/lock.yaml"
"$BIN/hcosim" up "$WORK/lock.yaml" --out "$WORK/l" >"$WORK/lock.log" 2>&1
code=$?
[ $code -eq 2 ] || fail "lockstep with on_failure: ignore exited $code, expected 2"
grep -qE "lock.yaml:12:17: on_failure: ignore needs mode realtime" "$WORK/lock.log" ||
  fail "the refusal does not name the file and line: $(cat "$WORK/lock.log")"
"$BIN/hcosim" up "$WORK/restart.yaml" --mode lockstep --out "$WORK/l" >"$WORK/lock2.log" 2>&1
[ $? -eq 2 ] || fail "--mode lockstep with on_failure: restart was not refused"
grep -qE "restart.yaml:12:17: on_failure: restart needs mode realtime" "$WORK/lock2.log" ||
  fail "the refusal does not name the file and line: $(cat "$WORK/lock2.log")"

for log in restart restart2 ignore; do
  for pid in $(sed -nE 's/.*pid ([0-9]+).*/\1/p' "$WORK/$log.log"); do
    alive "$pid" && fail "$log: process $pid still running after up exited"
  done
done
shm_after=$(shm_segments)
[ "$shm_after" -le "$shm_before" ] || fail "shared-memory segments left behind: $shm_before before, $shm_after after"
[ -z "$(domain_ports)" ] || fail "port segments of domain $DOMAIN left behind: $(domain_ports)"
echo "policy_test: ok"

# A service that fails ends the run: up names it and its exit status, stops
# the others, and leaves no process behind. Ctrl-C stops everything in 2 s.
source "$(dirname "$0")/lib.sh"
deployment fail.yaml <<'YAML'
services:
  - name: steady
    kind: test_probe
    rate: 100
    params: {role: source}
  - name: flaky
    kind: test_probe
    rate: 100
    params: {role: wall, fail_after: 1}
YAML
limit 30 "$BIN/hcosim" up "$WORK/fail.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1
code=$?
[ $code -eq 1 ] || fail "up exited $code, expected 1"
grep -q "service 'flaky' ended (exit status 3)" "$WORK/up.log" || fail "failure not named"
for pid in $(sed -nE 's/.*started +[a-z]+ +pid ([0-9]+).*/\1/p' "$WORK/up.log"); do
  alive "$pid" && fail "process $pid still running after up exited"
done

# Ctrl-C while running without a duration.
sed -i 's/fail_after: 1/fail_after: 0/' "$WORK/fail.yaml"
"$BIN/hcosim" up "$WORK/fail.yaml" --out "$WORK/out" >"$WORK/up2.log" 2>&1 &
up=$!
# Both started lines, waited for: under sanitizers and a parallel test the
# second can come after a fixed 2 s.
for _ in $(seq $((40 * SLOWDOWN))); do
  pids=$(sed -nE 's/.*started +[a-z]+ +pid ([0-9]+).*/\1/p' "$WORK/up2.log")
  [ "$(echo "$pids" | wc -w)" -eq 2 ] && break
  sleep 0.1
done
sleep 2
[ "$(echo "$pids" | wc -w)" -eq 2 ] || fail "expected 2 services started: $(cat "$WORK/up2.log")"
t0=$(date +%s%N)
kill -INT $up
wait $up
code=$?
ms=$(( ($(date +%s%N) - t0) / 1000000 ))
[ $code -eq 0 ] || fail "up exited $code after SIGINT"
[ $ms -lt 2500 ] || fail "stopping took $ms ms"
grep -q "stopped by SIGINT" "$WORK/up2.log" || fail "no stop message"
for pid in $pids; do alive "$pid" && fail "service $pid survived Ctrl-C"; done
grep -q "steady .*exit status 0" "$WORK/up2.log" || fail "steady did not exit cleanly: $(cat "$WORK/up2.log")"

# A service that refuses its params is not restarted (it would be refused
# again), and up shows its error, with the file and line.
deployment refuse.yaml <<'YAML'
services:
  - {name: steady, kind: test_probe, rate: 100, params: {role: source}}
  - {name: picky, kind: test_probe, rate: 100, on_failure: restart, params: {role: wall, colour: red}}
YAML
limit 30 "$BIN/hcosim" up "$WORK/refuse.yaml" --out "$WORK/out3" >"$WORK/up3.log" 2>&1
code=$?
[ $code -eq 1 ] || fail "up with a refused service exited $code, expected 1"
grep -q "service 'picky' ended (exit status 2 before its loop ran; a refused configuration is not restarted)" \
  "$WORK/up3.log" || fail "the refusal was not named: $(cat "$WORK/up3.log")"
grep -q "^  picky: hcosim_test_probe: .*refuse.yaml:4:.*unknown key 'colour'" "$WORK/up3.log" ||
  fail "up did not show picky's error: $(cat "$WORK/up3.log")"
grep -q "restarting it" "$WORK/up3.log" && fail "picky was restarted: $(cat "$WORK/up3.log")"
for pid in $(sed -nE 's/.*started +[a-z]+ +pid ([0-9]+).*/\1/p' "$WORK/up3.log"); do
  alive "$pid" && fail "process $pid still running after up exited"
done

# A bad file starts nothing: up exits 2 and says where the problem is.
refused() {  # NAME YAML MESSAGE
  printf '%b' "$2" >"$WORK/$1.yaml"
  local err code
  err=$("$BIN/hcosim" up "$WORK/$1.yaml" 2>&1); code=$?
  [ $code -eq 2 ] || fail "$1.yaml exited $code, not 2: $err"
  echo "$err" | grep -q -- "$1.yaml:$3" || fail "$1.yaml: expected '$3': $err"
}
refused bad 'domain: 1\nservices:\n  - {name: a, kind: test_probe, rte: 5}\n' \
  "3:33: unknown key 'rte'; did you mean 'rate'?"
refused bad2 'services:\n  - {name: a, kind: warp_drive, rate: 5}\n' \
  "2:1: no service of kind 'warp_drive' (known kinds: .*test_probe"
# A file with nothing to run is a mistake, not a run of the clock alone.
refused empty 'mode: lockstep\nduration: 1\n' "1:1: nothing to run: the deployment lists no services"
refused unneeded 'scene:\n  objects: []\nservices:\n  - {name: cam, kind: tracker, rate: 10}\n' \
  "4:3: nothing to run: the scene needs none of its services"
echo "failure_test: ok (stopped in $ms ms)"

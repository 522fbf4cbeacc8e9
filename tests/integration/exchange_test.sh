# Two service processes started by hcosim up exchange HapticState and
# ForceFeedback over Fast DDS; a third sends NaN samples that are refused
# and counted in ServiceStatus, and never answered. up prints its progress.
source "$(dirname "$0")/lib.sh"
deployment up.yaml <<'YAML'
mode: realtime
duration: 4
services:
  - name: src
    kind: test_probe
    rate: 500
    params: {role: source, nan_every: 5}
  - name: wall
    kind: test_probe
    rate: 1000
    params: {role: wall, stiffness: 800}
YAML
start status "$BIN/hcosim" echo ServiceStatus --count 0 --timeout 8
# 400 answers span a second of the source's 1 Hz stroke: its contact half included,
# however early echo joins (200 from the start ended just before contact).
start force "$BIN/hcosim" echo ForceFeedback --count 400 --timeout 8
limit 30 "$BIN/hcosim" up "$WORK/up.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?"
grep -q "duration reached" "$WORK/up.log" || fail "up did not run to its duration"
grep -qE "^hcosim up: every service joined domain $DOMAIN in [0-9.]+ s$" "$WORK/up.log" ||
  fail "up did not report the services joining: $(cat "$WORK/up.log")"
# The progress line: simulated time, pace, and every service's rate and
# overruns (and the outputs it shed, once it has shed some).
grep -qE "^sim [0-9.]+ s, real-time factor (0\.9|1\.0)[0-9] \| src [0-9]+ Hz, [0-9]+ overruns(, [0-9]+ shed)? \| wall [0-9]+ Hz, [0-9]+ overruns(, [0-9]+ shed)?$" \
  "$WORK/up.log" || fail "no progress line with both services: $(cat "$WORK/up.log")"
line=$(grep "probe src:" "$WORK/out/logs/src.log") || fail "no summary from src"
sent=$(echo "$line" | sed -nE 's/.*sent ([0-9]+).*/\1/p')
answers=$(echo "$line" | sed -nE 's/.*answers ([0-9]+).*/\1/p')
[ "$sent" -gt 1000 ] || fail "src sent only $sent samples in 4 s at 500 Hz"
# One in five samples is NaN and must go unanswered; the rest are answered
# unless best-effort delivery lost them (rare on loopback).
awk -v a="$answers" -v s="$sent" 'BEGIN { exit !(a >= 0.3 * s && a <= 0.8 * s + 5) }' ||
  fail "wall answered $answers of $sent (expected about 80%): $line"
wait "${PIDS[1]}"
grep -q '"source":"wall"' "$WORK/force.log" || fail "no ForceFeedback from wall on the wire"
grep -q '"in_contact":true' "$WORK/force.log" || fail "wall never reported contact"
grep -v '^{' "$WORK/force.log" | grep -q . && fail "non-JSON output from echo"
grep -q 'null' "$WORK/force.log" && fail "a non-finite force reached the wire"
wait "${PIDS[0]}"
grep '"service":"wall"' "$WORK/status.log" | grep -q '"samples_rejected":[1-9]' || fail "wall did not count rejections"
grep '"service":"wall"' "$WORK/status.log" | grep -q 'HapticState: position.x is NaN' || fail "rejection reason missing"
# A domain whose UDP ports meet the machine's ephemeral ones is warned of
# (docs/deployment.md); this test's own is not.
grep -q "warning: domain" "$WORK/up.log" && fail "up warned of domain $DOMAIN: $(grep warning "$WORK/up.log")"
read -r lo hi </proc/sys/net/ipv4/ip_local_port_range
if [ "$lo" -le 49649 ] && [ "$hi" -ge 49400 ]; then
  sed -E 's/^domain: .*/domain: 168/; s/^duration: .*/duration: 0.5/' "$WORK/up.yaml" >"$WORK/ephemeral.yaml"
  limit 30 "$BIN/hcosim" up "$WORK/ephemeral.yaml" --out "$WORK/ephemeral" >"$WORK/ephemeral.log" 2>&1
  grep -qE "^hcosim up: warning: domain 168's UDP ports \(49400 to 49649\) lie in this machine's ephemeral port range \($lo to $hi," \
    "$WORK/ephemeral.log" || fail "no warning of domain 168's ports: $(cat "$WORK/ephemeral.log")"
fi
echo "exchange_test: ok ($answers of $sent answered)"

# Lockstep: the clock drives every service step by step, with multi-rate
# decimation, and the run ends by itself at the duration.
source "$(dirname "$0")/lib.sh"
deployment lockstep.yaml <<'YAML'
mode: lockstep
step: 0.001
duration: 0.5
services:
  - name: fast
    kind: test_probe
    rate: 1000
    params: {role: source}
  - name: slow
    kind: test_probe
    rate: 250
    params: {role: wall}
YAML
for run in 1 2; do
  limit 60 "$BIN/hcosim" up "$WORK/lockstep.yaml" --out "$WORK/out" >"$WORK/up$run.log" 2>&1 || fail "up exited $?"
  grep -q "lockstep run complete" "$WORK/up$run.log" || fail "lockstep did not complete"
  grep -q "probe fast: role source, steps 500," "$WORK/out/logs/fast.log" || fail "fast did not take exactly 500 steps"
  grep -q "probe slow: role wall, steps 125," "$WORK/out/logs/slow.log" || fail "slow did not take exactly 125 steps"
  grep -q "clock: 500 steps, 0.500 s simulated" "$WORK/out/logs/clock.log" || fail "clock summary wrong"
done
echo "lockstep_test: ok"

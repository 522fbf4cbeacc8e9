# The haptic loop as the hand meets it (docs/haptic.md, "The loop").
# 1. Real time, a device and two sources (a rigid cube, an elastic sheet)
#    for 10 s: at least 99 % of ticks answered by every source within the
#    tick (a loop that works; the bench judges the goal, 99.9 %,
#    docs/PERFORMANCE.md), or, where the machine does not give bare Fast
#    DDS that much, what a bare pair beside it gets, less 0.01, in the
#    first run or, where that falls short, a second one (below)
#    (within_bare in lib.sh: a shared machine may not give a bare pair
#    99 % within 0.8 ms, `hcosim bench haptic --quick` shows what it does).
#    Sources answer on their receiving thread: a thread of their own adds
#    a hand-over to every answer, which this bound catches.
#    A source far from the stylus answers with free space around it, which
#    the device renders without waiting (docs/haptic.md, "Free space").
# 2. A source that answers 3 ms late (a linear wall): the device renders
#    its local model, so the force it outputs is the wall's at the current
#    position (within rounding), its step from tick to tick never larger
#    than the wall's stiffness times that tick's motion, and the late
#    answers agree with what was rendered in their place.
# 3. Lockstep: the force the device outputs at step k is the sum of its
#    sources' answers to its state k (the Gauss-Seidel group).
source "$(dirname "$0")/lib.sh"
cat >"$WORK/tour.yaml" <<'YAML'
start: [0, 0, 0.05]
actions:
  - move_to: {to: [-0.03, 0, 0.023], speed: 0.05}
  - press: {depth: 0.008, speed: 0.01}
  - hold: {duration: 1}
  - release: {speed: 0.02}
  - move_to: {to: [0.03, 0, 0.024], speed: 0.05}
  - press: {depth: 0.01, speed: 0.01}
  - hold: {duration: 1}
  - release: {speed: 0.02}
  - hold: {duration: 10}
YAML
deployment realtime.yaml <<'YAML'
mode: realtime
duration: 10
scene:
  objects:
    - {name: cube, kind: rigid, shape: cube, size: 0.01, mass: 0.05, centre: [-0.03, 0, 0.01]}
    - {name: sheet, kind: deformable, model: sheet, centre: [0.03, 0, 0.02], size: 0.03}
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: tour.yaml, centre: [0, 0, 0.02], report: omni.json}
  - name: bodies
    kind: rigid
    rate: 1000
  - name: objects
    kind: deformable
    rate: 1000
YAML
# One real-time run with a bare pair beside it: sets RT (its outputs), UP
# (up's log), SUMMARY (the device's), RATIO and BARE.
loop_run() {
  RT="$WORK/rt$1" UP="$WORK/up$1.log"
  start "up$1" "$BIN/hcosim" up "$WORK/realtime.yaml" --out "$RT"
  running_then_bare "$UP" 8
  wait "${PIDS[-1]}" || fail "real-time up exited $?"
  SUMMARY=$(grep "omni:.*ticks" "$RT/logs/omni.log") || fail "no summary from the device"
  echo "$SUMMARY"
  RATIO=$(jq -r .on_time_ratio "$WORK/omni.json")
  echo "haptic_loop_test: run $1: $RATIO of ticks answered within the tick; bare Fast DDS beside it: $BARE"
}
# A second run where the first falls short: on a noisy host the loop, three
# real-time processes, loses more to a stall than the bare pair does, now
# and then; a loop that is broken falls short in both runs.
loop_run 1
if ! within_bare "$RATIO"; then
  echo "haptic_loop_test: run 1 fell short; once more"
  loop_run 2
fi
grep -q "omni  *scheduling: " "$UP" || fail "up does not show the device's scheduling: $(cat "$UP")"
within_bare "$RATIO" || fail "only $RATIO of ticks answered within the tick (bare Fast DDS beside it: $BARE): $SUMMARY"
grep -q "states in contact" "$RT/logs/bodies.log" || fail "no rigid summary"
awk '/states in contact/ { for (i = 1; i <= NF; i++) if ($(i + 1) == "states" && $(i + 2) == "in") n = $i } END { exit !(n > 100) }' \
  "$RT/logs/bodies.log" || fail "the stylus never pressed the cube: $(grep 'states in contact' "$RT/logs/bodies.log")"
grep -qE "^sheet: [1-9][0-9]* ticks in contact" "$RT/logs/objects.log" || fail "the stylus never pressed the sheet"
# While the stylus presses one object the other is far: its free-space
# answers cover the HIP, the device renders it without waiting, and its
# service leaves most states unanswered (a refresh every 10 ms).
covered=$(jq -r .covered "$WORK/omni.json")
[ "$covered" -gt 3000 ] || fail "only $covered source-ticks covered by a free-space answer: $SUMMARY"
for s in bodies:body objects:object; do
  n=$(sed -nE "s/^${s%%:*}: ([0-9]+) ${s#*:}-states left to a free-space answer$/\1/p" "$RT/logs/${s%%:*}.log")
  [ "${n:-0}" -gt 2000 ] || fail "${s%%:*} left ${n:-no} states to a free-space answer"
done

# 2. A wall answering 3 ms late; passivity off, so that what the device
# outputs is what it rendered; source_timeout 0.5 s, so that a stall of
# this machine (the wall once fell silent for 0.09 s here, in a full ctest
# run, and its force was dropped, as it should be) does not take the wall
# out of what is judged here: rendering a late answer's local model.
cat >"$WORK/press.yaml" <<'YAML'
start: [0, 0, 0.01]
actions:
  - press: {depth: 0.02, speed: 0.02}
  - hold: {duration: 0.5}
  - release: {speed: 0.02}
  - press: {depth: 0.02, speed: 0.04}
  - hold: {duration: 3}
YAML
deployment late.yaml <<'YAML'
mode: realtime
duration: 4
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: press.yaml, passivity: off, source_timeout: 0.5, report: late.json}
  - name: wall
    kind: test_probe
    rate: 1000
    priority: 30  # a force source, as the rigid and deformable kinds are by default
    params: {role: wall, stiffness: 500, delay: 0.003}
YAML
start state "$BIN/hcosim" echo HapticState --count 0
limit 30 "$BIN/hcosim" up "$WORK/late.yaml" --out "$WORK/late" >"$WORK/late.log" 2>&1 || fail "up exited $?"
stop_echoes "${PIDS[-1]}"
grep "omni:" "$WORK/late/logs/omni.log"
modelled=$(jq -r .modelled "$WORK/late.json")
[ "$modelled" -gt 1000 ] || fail "only $modelled ticks rendered from the wall's local model"
# Consecutive states k, k+1: F_k = rendered_force of k+1 answers x_k.
jq -r 'select(.device == "omni") | [.seq, .position.x, .position.y, .position.z,
       .rendered_force.x, .rendered_force.y, .rendered_force.z] | @tsv' "$WORK/state.log" | sort -n >"$WORK/ticks.tsv"
[ "$(wc -l <"$WORK/ticks.tsv")" -gt 2000 ] || fail "only $(wc -l <"$WORK/ticks.tsv") device states on the wire"
awk -F'\t' -v k=500 '
  { seq[NR] = $1; x[NR] = $2; y[NR] = $3; z[NR] = $4; fz[NR] = $7 }
  END {
    for (i = 1; i < NR; i++) {
      if (seq[i + 1] != seq[i] + 1) continue
      # F rendered at tick seq[i] (carried by state seq[i] + 1) against the wall at x of seq[i].
      wall = z[i] < 0 ? -k * z[i] : 0
      err = fz[i + 1] - wall; if (err < 0) err = -err
      if (err > worst) worst = err
      pairs++
      if (i > 1 && seq[i] == seq[i - 1] + 1) {
        dx = sqrt((x[i] - x[i - 1]) ^ 2 + (y[i] - y[i - 1]) ^ 2 + (z[i] - z[i - 1]) ^ 2)
        step = fz[i + 1] - fz[i]; if (step < 0) step = -step
        if (step > k * dx + 1e-6) { bad++; if (step - k * dx > over) over = step - k * dx }
      }
      if (wall > peak) peak = wall
    }
    printf "late wall: %d tick pairs, force off the wall by at most %.2e N of %.3f N, %d steps over k |dx| (by %.2e N)\n",
      pairs, worst, peak, bad, over
    exit !(pairs > 2000 && peak > 1 && worst < 1e-3 && bad == 0)
  }' "$WORK/ticks.tsv" || fail "the device did not render the late wall's local model"
err=$(jq -r .force_error_p99_n "$WORK/late.json")
awk -v e="$err" 'BEGIN { exit !(e < 1e-3) }' || fail "late answers differ from what was rendered: p99 $err N"

# 3. Lockstep: the answer to state k is rendered at step k.
deployment lockstep.yaml <<'YAML'
mode: lockstep
duration: 2
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: tour.yaml, centre: [0, 0, 0.02], passivity: off}
  - name: bodies
    kind: rigid
    rate: 1000
    params:
      device: omni
      bodies: [{name: cube, shape: cube, size: 0.01, mass: 0.05, centre: [-0.03, 0, 0.01]}]
YAML
limit 60 "$BIN/hcosim" up "$WORK/lockstep.yaml" --out "$WORK/ls" --record "$WORK/ls.rec" >"$WORK/ls.log" 2>&1 ||
  fail "lockstep up exited $?: $(tail -n 5 "$WORK/ls.log")"
"$BIN/hcosim" export "$WORK/ls.rec" --topic HapticState >"$WORK/hs.jsonl" || fail "export HapticState"
"$BIN/hcosim" export "$WORK/ls.rec" --topic ForceFeedback >"$WORK/ff.jsonl" || fail "export ForceFeedback"
jq -r '[.seq, .rendered_force.z] | @tsv' "$WORK/hs.jsonl" | sort -n >"$WORK/rendered.tsv"
jq -r '[.answers_seq, .force.z, .in_contact] | @tsv' "$WORK/ff.jsonl" | sort -n >"$WORK/answers.tsv"
# Every step from the first: the recording holds each writer's samples
# from step 0 (services/runtime/recordings.h).
awk -F'\t' '
  NR == FNR { f[$1] += $2; if ($3 == "true") touched[$1] = 1; next }
  { r[$1] = $2; n = $1 > n ? $1 : n }
  END {
    for (k0 = 0; k0 < n && !((k0 in f) && ((k0 + 1) in r)); k0++) {}
    for (k = k0; k < n; k++) {
      if (!(k in f) || !((k + 1) in r)) { missing++; continue }
      d = r[k + 1] - f[k]; if (d < 0) d = -d
      if (d > worst) worst = d
      checked++; contact += (k in touched)
    }
    printf "lockstep: %d steps checked from step %d, %d in contact, %d without an answer, worst |rendered - answer| %.2e N\n",
      checked, k0, contact, missing, worst
    exit !(k0 == 0 && checked > 1800 && contact > 100 && missing == 0 && worst < 1e-12)
  }' "$WORK/answers.tsv" "$WORK/rendered.tsv" || fail "the device did not render the answer to its state of the same step"
echo "haptic_loop_test: ok"

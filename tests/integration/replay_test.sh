# hcosim replay: the stylus of a recorded lockstep run of deploy/press.yaml,
# replayed alone into a real-time deformable service, presses the cube again: the service answers with contact forces like the
# recorded ones. Replaying a file that is not a recording, or topics it
# does not hold, fails with a message.
source "$(dirname "$0")/lib.sh"
from_deploy press.yaml
limit 60 "$BIN/hcosim" up "$WORK/press.yaml" --record "$WORK/run.rec" --out "$WORK/out" >"$WORK/up.log" 2>&1 ||
  fail "recording run: up exited $?"
recorded=$("$BIN/hcosim" export "$WORK/run.rec" --topic ForceFeedback 2>/dev/null | grep -c '"in_contact":true')
[ "$recorded" -gt 100 ] || fail "the recorded run has only $recorded contact forces"

# The same cube, alone, in real time; the replay is its only stylus.
cube_alone alone.yaml 12
start forces "$BIN/hcosim" echo ForceFeedback --count 0 --timeout 11
start up "$BIN/hcosim" up "$WORK/alone.yaml" --out "$WORK/alone"
# replay waits for the service's reader (it builds its model first).
limit 30 "$BIN/hcosim" replay "$WORK/run.rec" --topics HapticState >"$WORK/replay.log" 2>&1 ||
  fail "replay exited $?: $(cat "$WORK/replay.log")"
grep -q "published 2000 samples" "$WORK/replay.log" || fail "replay did not publish the 2000 states: $(cat "$WORK/replay.log")"
wait "${PIDS[0]}"
# The service answers every tick with the newest state, so count the
# replayed states it found in contact: over half the recorded ones (real
# time loses ticks to scheduling: 63% once with another test running on
# the two cores), and no more.
replayed=$(jq -s '[.[] | select(.source == "cube" and .in_contact) | .answers_seq] | unique | length' "$WORK/forces.log")
[ "$replayed" -gt $((recorded / 2)) ] && [ "$replayed" -le $((recorded + 5)) ] ||
  fail "the replayed press touched in $replayed states, the recording in $recorded"

"$BIN/hcosim" replay "$WORK/alone.yaml" >"$WORK/bad.log" 2>&1 && fail "replaying a YAML file succeeded"
grep -q "alone.yaml: not an hcosim recording" "$WORK/bad.log" || fail "message: $(cat "$WORK/bad.log")"
"$BIN/hcosim" replay "$WORK/run.rec" --topics MarkerPose >"$WORK/bad.log" 2>&1 && fail "replaying an absent topic succeeded"
grep -q "no sample of the chosen topics" "$WORK/bad.log" || fail "message: $(cat "$WORK/bad.log")"
echo "replay_test: ok ($replayed of $recorded states in contact)"

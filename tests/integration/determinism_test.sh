# Lockstep runs are reproducible across processes: deploy/press.yaml
# (the virtual user presses the hybrid cube through the simulated Omni),
# with a sheet and a dome beside the cube, run twice for 2 s with --record
# exports the same DeformedMesh, ForceFeedback and HapticState lines, bit
# for bit, though DDS delivers samples in its own order each time (the
# three objects' meshes of one step too: export orders them by key). The
# press reaches the cube, so the outputs depend on the exchange between
# the two services.
source "$(dirname "$0")/lib.sh"
from_deploy press.yaml
sed -i '/- {name: cube, kind: deformable/a\
    - {name: sheet, kind: deformable, model: sheet, centre: [0.12, 0, 0.02], size: 0.04}\
    - {name: dome, kind: deformable, model: semisphere, centre: [-0.12, 0, 0], size: 0.02}' "$WORK/press.yaml"
grep -q "name: dome" "$WORK/press.yaml" || fail "the sheet and dome were not added: $(cat "$WORK/press.yaml")"
for run in 1 2; do
  limit 90 "$BIN/hcosim" up "$WORK/press.yaml" --mode lockstep --duration 2 --record "$WORK/run$run.rec" \
    --out "$WORK/out$run" >"$WORK/up$run.log" 2>&1 || fail "run $run: up exited $?"
  grep -q "lockstep run complete" "$WORK/up$run.log" || fail "run $run did not complete"
  for topic in DeformedMesh ForceFeedback HapticState; do
    "$BIN/hcosim" export "$WORK/run$run.rec" --topic $topic >"$WORK/$topic.$run.jsonl" 2>/dev/null ||
      fail "run $run: export of $topic exited $?"
  done
done
[ "$(wc -l <"$WORK/HapticState.1.jsonl")" -eq 2000 ] || fail "run 1 did not record 2000 HapticStates"
[ "$(wc -l <"$WORK/DeformedMesh.1.jsonl")" -ge 50 ] || fail "run 1 recorded fewer than 50 meshes"
grep -q '"in_contact":true' "$WORK/ForceFeedback.1.jsonl" || fail "the press never reached the cube"
for topic in DeformedMesh ForceFeedback HapticState; do
  cmp -s "$WORK/$topic.1.jsonl" "$WORK/$topic.2.jsonl" ||
    fail "$topic differs between two runs from line $(cmp "$WORK/$topic.1.jsonl" "$WORK/$topic.2.jsonl" | awk '{ print $NF }')"
done
echo "determinism_test: ok ($(wc -l <"$WORK/DeformedMesh.1.jsonl") meshes, $(wc -l <"$WORK/ForceFeedback.1.jsonl") forces identical)"

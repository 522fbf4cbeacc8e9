# MCAP recordings checked by the clients robotics users open them with:
# MCAP's and Foxglove's own libraries from npm (tests/interop/mcap, pinned
# by its lockfile, installed by deploy/setup.sh), not a reader written
# here. A lockstep run of the default deployment recorded to MCAP is read
# back by @mcap/core (every CRC checked, a seek through the indexes), every
# schema parsed by @foxglove/omgidl-parser and every message decoded by
# @foxglove/omgidl-serialization to what `hcosim export` prints; the same
# run recorded in hcosim's format exports the same samples. A file that
# @mcap/core writes replays into a service as hcosim's own do, and an lz4
# recording from `hcosim record` reads back too. Foxglove's scene channels
# decode with their schemas and match the topics they come from.
source "$(dirname "$0")/lib.sh"
clients=$(cd "$(dirname "$0")/../interop/mcap" && pwd)
if [ ! -d "$clients/node_modules/@mcap/core" ] || ! command -v node >/dev/null; then
  echo "mcap_test: SKIPPED: no node or no npm modules in $clients (deploy/setup.sh installs them; npm ci there)"
  exit 77
fi
topics="HapticState ForceFeedback MarkerPose CameraFrame RigidBodyState RigidDivergence DeformedMesh
  DeformedMeshTopology ServiceStatus ClockTick StepDone"
from_deploy default.yaml
for rec in run.mcap run.rec; do
  limit 120 "$BIN/hcosim" up "$WORK/default.yaml" --duration 1 --mode lockstep --record "$WORK/$rec" \
    --out "$WORK/out_$rec" >"$WORK/up_$rec.log" 2>&1 || fail "up --record $rec exited $?"
done
recorded=$(sed -nE 's/.*recorded ([0-9]+) samples to .*run.mcap.*/\1/p' "$WORK/up_run.mcap.log")
[ -n "$recorded" ] || fail "up did not say what it recorded"
mkdir "$WORK/export"
for t in $topics; do
  "$BIN/hcosim" export "$WORK/run.mcap" --topic "$t" --wall >"$WORK/export/$t.jsonl" 2>>"$WORK/export.log" ||
    fail "export $t exited $?"
done
# The topics a lockstep run reproduces bit for bit (integration.determinism).
for t in HapticState ForceFeedback DeformedMesh; do
  "$BIN/hcosim" export "$WORK/run.mcap" --topic "$t" >"$WORK/$t.mcap.jsonl" 2>/dev/null
  "$BIN/hcosim" export "$WORK/run.rec" --topic "$t" >"$WORK/$t.rec.jsonl" 2>/dev/null
  cmp -s "$WORK/$t.mcap.jsonl" "$WORK/$t.rec.jsonl" ||
    fail "$t exports otherwise from MCAP than from hcosim's format of the same lockstep run" \
      "($(wc -l <"$WORK/$t.mcap.jsonl") and $(wc -l <"$WORK/$t.rec.jsonl") lines; the first that differ:" \
      "$(diff "$WORK/$t.mcap.jsonl" "$WORK/$t.rec.jsonl" | head -c 1500))"
done
[ "$(wc -l <"$WORK/export/CameraFrame.jsonl")" -gt 0 ] && [ "$(wc -l <"$WORK/export/DeformedMesh.jsonl")" -gt 0 ] ||
  fail "the recording lacks camera frames or meshes"
node "$clients/check_mcap.mjs" "$WORK/run.mcap" "$WORK/export" >"$WORK/check.log" 2>&1 ||
  fail "@mcap/core and omgidl: $(cat "$WORK/check.log")"
grep -q "^check_mcap: $recorded messages on 1[01] channels and [0-9]* on [0-9]* scene channels .*(zstd), CRCs checked, .*; $recorded decoded equal hcosim export" \
  "$WORK/check.log" || fail "check: $(cat "$WORK/check.log"), up recorded $recorded"
# Foxglove's scene channels: every object of the default scene, the
# stylus, the camera's pose and its frames.
for channel in scene/box scene/ball scene/sheet scene/dome scene/cube scene/organ scene/stylus tf image/cam; do
  grep -qE "scene: .*\b$channel [1-9]" "$WORK/check.log" || fail "no $channel in: $(cat "$WORK/check.log")"
done

# Written by @mcap/core: the press of deploy/press.yaml's stylus, replayed
# into the cube alone in real time, touches it again.
from_deploy press.yaml
limit 60 "$BIN/hcosim" up "$WORK/press.yaml" --record "$WORK/press.mcap" --out "$WORK/out_press" \
  >"$WORK/up_press.log" 2>&1 || fail "press run: up exited $?"
node "$clients/write_mcap.mjs" "$WORK/press.mcap" "$WORK/js.mcap" >"$WORK/write.log" 2>&1 ||
  fail "@mcap/core writer: $(cat "$WORK/write.log")"
cmp -s <("$BIN/hcosim" export "$WORK/js.mcap" --topic HapticState --wall 2>/dev/null) \
  <("$BIN/hcosim" export "$WORK/press.mcap" --topic HapticState --wall 2>/dev/null) ||
  fail "@mcap/core's file exports other states than the recording it came from"
recorded_contact=$("$BIN/hcosim" export "$WORK/press.mcap" --topic ForceFeedback 2>/dev/null | grep -c '"in_contact":true')
cube_alone alone.yaml 12
start forces "$BIN/hcosim" echo ForceFeedback --count 0 --timeout 11
start alone "$BIN/hcosim" up "$WORK/alone.yaml" --out "$WORK/alone"
limit 30 "$BIN/hcosim" replay "$WORK/js.mcap" >"$WORK/replay.log" 2>&1 || fail "replay exited $?: $(cat "$WORK/replay.log")"
grep -q "published 2000 samples" "$WORK/replay.log" || fail "replay: $(cat "$WORK/replay.log")"
wait "${PIDS[0]}"
replayed=$(jq -s '[.[] | select(.source == "cube" and .in_contact) | .answers_seq] | unique | length' "$WORK/forces.log")
[ "$replayed" -gt $((recorded_contact / 2)) ] && [ "$replayed" -le $((recorded_contact + 5)) ] ||
  fail "@mcap/core's file touched in $replayed states, the recording in $recorded_contact"

# lz4 from hcosim record, beside a real-time run.
start lz4 "$BIN/hcosim" record "$WORK/lz4.mcap" --compression lz4 --no-scene --topics HapticState,ForceFeedback,DeformedMesh \
  --duration $((4 * SLOWDOWN))
sleep 1
limit 30 "$BIN/hcosim" up "$WORK/press.yaml" --mode realtime --duration 2 --out "$WORK/out_rt" >"$WORK/up_rt.log" 2>&1 ||
  fail "real-time run exited $?"
wait "${PIDS[-1]}" || fail "record --compression lz4 exited $?: $(cat "$WORK/lz4.log")"
mkdir "$WORK/export_lz4"
for t in HapticState ForceFeedback DeformedMesh; do
  "$BIN/hcosim" export "$WORK/lz4.mcap" --topic "$t" --wall >"$WORK/export_lz4/$t.jsonl" 2>/dev/null
done
node "$clients/check_mcap.mjs" "$WORK/lz4.mcap" "$WORK/export_lz4" >"$WORK/check_lz4.log" 2>&1 ||
  fail "lz4: $(cat "$WORK/check_lz4.log")"
grep -q "on 3 channels and 0 on 0 scene channels .*(lz4)" "$WORK/check_lz4.log" || fail "lz4: $(cat "$WORK/check_lz4.log")"
echo "mcap_test: ok: $(cat "$WORK/check.log"); $(cat "$WORK/write.log"), $replayed of $recorded_contact states in contact replayed; $(cat "$WORK/check_lz4.log")"

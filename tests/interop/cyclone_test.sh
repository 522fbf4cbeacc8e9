# A Cyclone DDS participant joins a running hcosim service late and still
# rebuilds complete meshes: topology from the latched topic, positions from
# DeformedMesh (5402 vertices, the seed's visual mesh size); first from a
# probe writing known values, then from the deformable service's hybrid
# cube, with one reader there from the start and one joining late. Then
# Cyclone reads the rigid service's ForceFeedback to a device pressing a
# cube: contacts with their local force model, and free-space answers.
# usage: bash cyclone_test.sh BIN_DIR TEST_BIN_DIR DOMAIN READER
source "$(dirname "$0")/../integration/lib.sh"
READER=$4
probe liver 30 mesh ", vertices: 5402"
sleep 2  # the topology was written before the reader existed
out=$(limit 60 "$READER" "$DOMAIN" 5402 5 40 2>&1) || fail "cyclone reader: $out"
echo "$out"
echo "$out" | grep -q "topology of 'liver', version 1, 5402 vertices, 5400 triangles" || fail "topology: $out"

# The real deformable service in a deployment: one Cyclone reader is there
# before it starts (live), another joins 2 s later (late); both rebuild the
# hybrid cube's 5402-vertex visual mesh.
kill -TERM "${PIDS[0]}" && wait "${PIDS[0]}"  # the probe's meshes end here
cube_alone cube.yaml 8
"$READER" "$DOMAIN" 5402 10 30 model >"$WORK/live.log" 2>&1 &
live=$!
PIDS+=($live)
start up "$BIN/hcosim" up "$WORK/cube.yaml" --out "$WORK/out"
sleep 2
out=$(limit 30 "$READER" "$DOMAIN" 5402 10 20 model 2>&1) || fail "late cyclone reader: $out"
echo "late: $out"
echo "$out" | grep -q "topology of 'cube', version 1, 5402 vertices" || fail "late topology: $out"
wait $live || fail "live cyclone reader: $(cat "$WORK/live.log")"
echo "live: $(cat "$WORK/live.log")"
grep -q "topology of 'cube', version 1, 5402 vertices" "$WORK/live.log" || fail "live topology: $(cat "$WORK/live.log")"

# ForceFeedback, local force model and free space, read by Cyclone while a
# device presses a rigid cube and leaves it.
kill -TERM "${PIDS[-1]}" 2>/dev/null; wait "${PIDS[-1]}" 2>/dev/null
cat >"$WORK/press.yaml" <<'YAML'
start: [0, 0, 0.05]
actions:
  - move_to: {to: [0, 0, 0.023], speed: 0.05}
  - press: {depth: 0.006, speed: 0.01}
  - hold: {duration: 1}
  - release: {speed: 0.02}
  - move_to: {to: [0, 0, 0.06], speed: 0.05}
  - hold: {duration: 10}
YAML
deployment force.yaml <<'YAML'
mode: realtime
duration: 8
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: press.yaml, centre: [0, 0, 0]}
  - name: bodies
    kind: rigid
    rate: 1000
    params:
      device: omni
      bodies: [{name: cube, shape: cube, size: 0.01, mass: 0.05, centre: [0, 0, 0.01]}]
YAML
"$(dirname "$READER")/cyclone_force_reader" "$DOMAIN" 1000 25 >"$WORK/force.log" 2>&1 &
force=$!
PIDS+=($force)
start force_up "$BIN/hcosim" up "$WORK/force.yaml" --out "$WORK/force"
wait $force || fail "cyclone ForceFeedback reader: $(cat "$WORK/force.log")"
echo "force: $(cat "$WORK/force.log")"
echo "cyclone_test: ok"

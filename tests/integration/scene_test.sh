# The scene: services take their objects from it, and hcosim up starts only
# the services it needs. A rigid service serves the scene's rigid ball, a
# deformable one only the object it names; a tracker without a camera is
# not started, nor a rigid service once the scene has no rigid object, and
# the lockstep clock does not wait for them. The tracker takes the scene's
# camera and marker when there is one.
source "$(dirname "$0")/lib.sh"
printf 'start: [0, 0, 0.3]\nactions:\n  - hold: {duration: 1}\n' >"$WORK/hold.yaml"
deployment scene.yaml <<'YAML'
mode: lockstep
duration: 0.3
scene:
  marker: {family: tag36h11, id: 3, size: 0.04}
  objects:
    - {name: ball, kind: rigid, shape: sphere, size: 0.02, mass: 0.1, centre: [0.1, 0, 0.02]}
    - {name: sheet, kind: deformable, model: sheet, centre: [0.3, 0, 0], resolution: 11}
    - {name: cube, kind: deformable, model: hybrid, centre: [0, 0, 0.05], size: 0.1}
services:
  - {name: omni, kind: haptic, rate: 1000, params: {script: hold.yaml}}
  - {name: bodies, kind: rigid, rate: 1000, params: {device: omni}}
  - {name: sheets, kind: deformable, rate: 1000, objects: [sheet], params: {device: omni}}
  - {name: cam, kind: tracker, rate: 25}
YAML
limit 60 "$BIN/hcosim" up "$WORK/scene.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?: $(cat "$WORK/up.log")"
grep -q "not starting cam: the scene has no camera" "$WORK/up.log" || fail "the tracker was started: $(cat "$WORK/up.log")"
grep -q "lockstep run complete" "$WORK/up.log" || fail "the run did not complete"
grep -q "clock: 300 steps, .*, 3 followers" "$WORK/out/logs/clock.log" || fail "the clock: $(cat "$WORK/out/logs/clock.log")"
grep -q "^ball: sphere at \[0.1000, 0.0000, 0.0200\]" "$WORK/out/logs/bodies.log" ||
  fail "the rigid service did not serve the scene's ball: $(cat "$WORK/out/logs/bodies.log")"
grep -q "^sheet:" "$WORK/out/logs/sheets.log" || fail "the deformable service did not serve the sheet"
grep -q "^cube:" "$WORK/out/logs/sheets.log" && fail "the deformable service served the cube it did not name"

# Without the ball, no rigid service.
grep -v "name: ball" "$WORK/scene.yaml" >"$WORK/noball.yaml"
limit 60 "$BIN/hcosim" up "$WORK/noball.yaml" --out "$WORK/out1" >"$WORK/up1.log" 2>&1 || fail "up exited $?"
grep -q "not starting bodies: the scene has no rigid object" "$WORK/up1.log" || fail "$(cat "$WORK/up1.log")"
grep -q "clock: 300 steps, .*, 2 followers" "$WORK/out1/logs/clock.log" || fail "$(cat "$WORK/out1/logs/clock.log")"

# With a camera the tracker runs, with the marker's tag.
sed 's/^  marker:/  camera: {source: synthetic}\n  marker:/' "$WORK/scene.yaml" >"$WORK/camera.yaml"
limit 60 "$BIN/hcosim" up "$WORK/camera.yaml" --out "$WORK/out2" >"$WORK/up2.log" 2>&1 || fail "up exited $?"
grep -q "cam: synthetic camera: 640x480 at 25 Hz, tag36h11 id 3; tag36h11 tags of 0.04 m" "$WORK/out2/logs/cam.log" ||
  fail "the tracker did not take the scene's camera and marker: $(cat "$WORK/out2/logs/cam.log")"

# A service naming an object the scene lacks is refused where it names it.
sed 's/objects: \[sheet\]/objects: [sheat]/' "$WORK/scene.yaml" >"$WORK/bad.yaml"
"$BIN/hcosim" up "$WORK/bad.yaml" --out "$WORK/out3" >"$WORK/bad.log" 2>&1
[ $? -eq 2 ] || fail "an undefined object reference was not refused: $(cat "$WORK/bad.log")"
grep -qE "bad.yaml:[0-9]+:[0-9]+: no object 'sheat' in the scene" "$WORK/bad.log" || fail "message: $(cat "$WORK/bad.log")"
echo "scene_test: ok"

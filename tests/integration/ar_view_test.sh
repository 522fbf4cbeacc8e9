# The AR view in real time keeps no queue: fed 30 camera frames a second
# while it draws only 10, it draws the newest frame each time, counts the
# ones it skipped, and repeats the frame before each gap in the video, so
# that the video keeps the camera's time (frames = drawn + skipped). A
# rigid box on the marker is drawn over the frames it gets. A looping
# 5-frame folder, whose frame numbers go back each loop, keeps being drawn.
source "$(dirname "$0")/lib.sh"
deployment ar.yaml <<'YAML'
mode: realtime
duration: 3
scene:
  marker: {id: 0, size: 0.03}
  camera: {source: synthetic, width: 320, height: 240, sheet: 4}
  objects:
    - {name: box, kind: rigid, shape: cube, size: 0.01, centre: [0.03, 0, 0.01]}
services:
  - {name: cam, kind: tracker, rate: 30}
  - {name: bodies, kind: rigid, rate: 200}
  - {name: view, kind: ar_view, rate: 10, params: {camera: cam, plots: off, fps: 30}}
YAML
limit 60 "$BIN/hcosim" up "$WORK/ar.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?"
view=$WORK/out/logs/view.log
read -r drawn skipped < <(sed -nE 's/^view: ([0-9]+) frames drawn, ([0-9]+) skipped \(late, or never sent\).*/\1 \2/p' "$view")
[ -n "$drawn" ] || fail "the view printed no summary"
# 3 s counted from when every service runs; the view may start a little earlier.
[ "$drawn" -ge 15 ] && [ "$drawn" -le 45 ] || fail "drew $drawn frames at 10 Hz in 3 s"
[ "$skipped" -ge "$drawn" ] || fail "skipped only $skipped of a camera three times faster than the view ($drawn drawn)"
written=$(sed -nE 's/^view: video .*, ([0-9]+) frames$/\1/p' "$view")
[ "$written" = $((drawn + skipped)) ] || fail "the video has $written frames, not drawn + skipped = $((drawn + skipped))"
"$BIN/hcosim" video "$WORK/out/ar.mp4" | grep -q ": $written frames, 320x240 at 30 fps, 0 blank" ||
  fail "the video read back: $("$BIN/hcosim" video "$WORK/out/ar.mp4" 2>&1)"
cover=$(sed -nE 's/.*the objects cover p50 ([0-9.]+)% of a frame.*/\1/p' "$view")
awk -v c="${cover:-0}" 'BEGIN { exit !(c > 0.2) }' || fail "the box covers ${cover:-no}% of a frame"
# A looping folder of 5 frames, drawn at the camera's rate for 2 s.
"$BIN/hcosim" synth --out "$WORK/seq" --frames 5 --tag-size 0.03 >/dev/null 2>&1 || fail "synth failed"
deployment loop.yaml <<YAML
mode: realtime
duration: 2
scene:
  marker: {id: 0, size: 0.03}
  camera: {source: folder, path: $WORK/seq/frames, camera: $WORK/seq/camera.yaml, loop: on}
  objects:
    - {name: box, kind: rigid, shape: cube, size: 0.01, centre: [0.03, 0, 0.01]}
services:
  - {name: cam, kind: tracker, rate: 20}
  - {name: view, kind: ar_view, rate: 20, params: {camera: cam, plots: off, video: ""}}
YAML
limit 60 "$BIN/hcosim" up "$WORK/loop.yaml" --out "$WORK/loop" >"$WORK/up_loop.log" 2>&1 || fail "loop run: up exited $?"
looped=$(sed -nE 's/^view: ([0-9]+) frames drawn.*/\1/p' "$WORK/loop/logs/view.log")
[ "${looped:-0}" -ge 20 ] || fail "drew ${looped:-no} frames of a looping 5-frame folder in 2 s at 20 Hz"

echo "ar_view_test: ok ($drawn drawn, $skipped skipped, $written in the video, box on ${cover}%, $looped frames of a 5-frame loop)"

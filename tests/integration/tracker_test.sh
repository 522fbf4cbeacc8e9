# The tracking service in real deployments. In real time: one tracker on
# the synthetic camera at 30 Hz (not a divisor of the 1 kHz base step,
# which real time allows), another on a folder of frames looping;
# MarkerPose and CameraFrame reach subscribers, the synthetic tracker's
# poses match the truth. A folder tracker that is not looping finishes the
# run at the end of its frames. In lockstep the tracker steps at its own
# rate. Bad configurations end with the file and line. The tracker does
# not link OpenCV's codecs.
source "$(dirname "$0")/lib.sh"
"$BIN/hcosim" synth --out "$WORK/s" --frames 10 >/dev/null 2>&1 || fail "synth exited $?"
deployment up.yaml <<'YAML'
mode: realtime
duration: 4
services:
  - name: cam
    kind: tracker
    rate: 30
    params: {source: synthetic, tag_id: 5}
  - name: files
    kind: tracker
    rate: 20
    params: {source: folder, path: s/frames, camera: s/camera.yaml, loop: on, frames: off}
YAML
start poses "$BIN/hcosim" echo MarkerPose --count 60 --timeout 10
start frames "$BIN/hcosim" echo CameraFrame --count 20 --timeout 10
limit 30 "$BIN/hcosim" up "$WORK/up.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?"
wait "${PIDS[0]}" || fail "fewer than 60 marker poses reached the subscriber"
wait "${PIDS[1]}" || fail "fewer than 20 camera frames reached the subscriber"
grep -q '"camera":"cam","tag_id":5,"family":"tag36h11"' "$WORK/poses.log" || fail "no pose of tag 5 from cam"
grep -q '"camera":"files","tag_id":0' "$WORK/poses.log" || fail "no pose from the folder tracker"
jq -e -s 'all(.[]; .latency_ms > 0 and .latency_ms < 1000 and .tag_size_m == 0.05 and .reprojection_error_px < 1
  and .tag_in_camera.position.z > 0.2 and .decision_margin > 50)' "$WORK/poses.log" >/dev/null ||
  fail "implausible marker poses: $(head -2 "$WORK/poses.log")"
jq -e -s 'all(.[]; .camera == "cam" and .encoding == "mono8" and .width == 640 and .data_bytes == 307200)' \
  "$WORK/frames.log" >/dev/null || fail "camera frames are not cam's 640x480 mono8: $(head -1 "$WORK/frames.log")"
truth=$(grep "against the synthetic truth" "$WORK/out/logs/cam.log") || fail "no accuracy summary from cam"
echo "$truth" | awk '{ for (i = 1; i <= NF; i++) if ($i == "p95") { v[++n] = $(i + 1) + 0 } }
  END { exit !(n == 2 && v[1] < 0.5 && v[2] < 2) }' || fail "cam's poses are off the truth: $truth"
grep -qE "^cam: [0-9]+ frames, .* 0 poses refused" "$WORK/out/logs/cam.log" || fail "no summary from cam"

# The shipped example, on this test's domain.
sed "s/^domain: 0/domain: $DOMAIN/" "$(dirname "$0")/../../deploy/tracker.yaml" >"$WORK/example.yaml"
limit 30 "$BIN/hcosim" up "$WORK/example.yaml" --out "$WORK/example" >"$WORK/example.log" 2>&1 ||
  fail "deploy/tracker.yaml: up exited $?"
grep -qE "^cam: [0-9]{2,} frames, .* 0 poses refused" "$WORK/example/logs/cam.log" ||
  fail "deploy/tracker.yaml tracked too few frames: $(cat "$WORK/example/logs/cam.log")"

# Without loop, the folder's end ends the run.
deployment once.yaml <<'YAML'
mode: realtime
duration: 20
services:
  - name: files
    kind: tracker
    rate: 50
    params: {source: folder, path: s/frames, camera: s/camera.yaml}
YAML
limit 30 "$BIN/hcosim" up "$WORK/once.yaml" --out "$WORK/once" >"$WORK/once.log" 2>&1 || fail "up exited $?"
grep -q "service 'files' finished" "$WORK/once.log" || fail "the run did not end with the frames: $(cat "$WORK/once.log")"
grep -q "the source ended after 10 frames" "$WORK/once/logs/files.log" || fail "the end of the frames was not said"
grep -q "10 frames, 10 with a tag, 10 detections" "$WORK/once/logs/files.log" || fail "not every frame was tracked"

# Lockstep: 1 s of simulated time at 25 Hz is 25 frames.
deployment lock.yaml <<'YAML'
mode: lockstep
duration: 1
services:
  - name: cam
    kind: tracker
    rate: 25
    params: {source: synthetic, frames: off}
YAML
limit 60 "$BIN/hcosim" up "$WORK/lock.yaml" --out "$WORK/lock" >"$WORK/lock.log" 2>&1 || fail "lockstep up exited $?"
grep -qE "^cam: 2[56] frames, 2[56] with a tag" "$WORK/lock/logs/cam.log" ||
  fail "lockstep did not give 25 frames: $(cat "$WORK/lock/logs/cam.log")"

# bad FILE CODE PATTERN: hcosim_tracker with FILE exits CODE and says PATTERN
bad() {
  "$BIN/hcosim_tracker" --name cam --rate 25 --domain "$DOMAIN" --deployment "$WORK/$1" >"$WORK/bad.log" 2>&1
  local got=$?
  [ $got -eq "$2" ] || fail "$1: exited $got, expected $2: $(cat "$WORK/bad.log")"
  grep -qE "$3" "$WORK/bad.log" || fail "$1: the error does not say '$3': $(cat "$WORK/bad.log")"
}
one() { printf 'services:\n  - name: cam\n    kind: tracker\n    rate: 25\n    params: %s\n' "$2" >"$WORK/$1"; }
one nocam.yaml "{source: video, path: s/frames}"
bad nocam.yaml 2 "nocam.yaml:5:[0-9]+: source 'video' needs camera"
one nopath.yaml "{source: folder, camera: s/camera.yaml, path: s/none}"
bad nopath.yaml 2 "nopath.yaml:5:[0-9]+: 'path': no file"
sed 's/rows: 3/rows: 2/' "$WORK/s/camera.yaml" >"$WORK/badcam.yaml"
one badcal.yaml "{source: folder, camera: badcam.yaml, path: s/frames}"
bad badcal.yaml 2 "badcam.yaml:[0-9]+:[0-9]+: 'camera_matrix' must be 3x3"
one typo.yaml "{source: synthetic, tag_sise: 0.05}"
bad typo.yaml 2 "typo.yaml:5:[0-9]+: unknown key 'tag_sise'; did you mean 'tag_size'"
one v4l2.yaml "{source: v4l2, device: /dev/video_hcosim_absent, camera: s/camera.yaml}"
bad v4l2.yaml 1 "V4L2 camera /dev/video_hcosim_absent: no such device"

# OpenCV's codecs, and the hundreds of libraries they bring, load only when
# a source needs them: the tracker itself does not link them.
if ldd "$BIN/hcosim_tracker" | grep -qE 'libopencv_(videoio|imgcodecs)'; then
  fail "hcosim_tracker links OpenCV's codecs: $(ldd "$BIN/hcosim_tracker" | grep -E 'videoio|imgcodecs')"
fi
echo "tracker_test: ok"

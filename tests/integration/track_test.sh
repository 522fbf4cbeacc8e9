# hcosim synth and hcosim track, offline: a synthetic orbit written as PNG
# frames and as an MJPG video is tracked back to its true poses, one JSON
# line per detection in frame order; frames without a tag and frames that
# do not decode are named and skipped; unreadable sources, bad intrinsics
# files and intrinsics of another frame size end with a clear message.
source "$(dirname "$0")/lib.sh"
S="$WORK/s"
# 40 frames at 2 Hz: the whole 20 s orbit, tilts up to 30 degrees.
"$BIN/hcosim" synth --out "$S" --frames 40 --rate 2 --video >"$WORK/synth.log" 2>&1 || fail "synth exited $?"
[ "$(ls "$S/frames" | wc -l)" -eq 40 ] || fail "synth did not write 40 frames"
[ "$(wc -l <"$S/truth.jsonl")" -eq 40 ] || fail "synth did not write 40 true poses"
grep -q "camera_matrix: !!opencv-matrix" "$S/camera.yaml" || fail "camera.yaml is not in OpenCV's format"

# track SOURCE NAME [extra args]: runs hcosim track against the truth; output in $WORK/NAME.{jsonl,log}
track() {
  local src=$1 name=$2
  shift 2
  "$BIN/hcosim" track --source "$src" --camera "$S/camera.yaml" --tag-size 0.05 --out "$WORK/$name.jsonl" \
    --truth "$S/truth.jsonl" "$@" >"$WORK/$name.log" 2>&1
}
# accuracy NAME TRANS_PCT ROT_DEG: the p95 errors of a track summary are within bounds
accuracy() {
  local line
  line=$(grep "true poses detected" "$WORK/$1.log") || fail "$1: no accuracy summary"
  echo "$line" | grep -q ": 40 of 40 true poses detected" || fail "$1: not every pose was detected: $line"
  echo "$line" | awk -v t="$2" -v r="$3" '{ for (i = 1; i <= NF; i++) { if ($i == "p95" && !tp) tp = $(i + 1) + 0
      else if ($i == "p95") rp = $(i + 1) + 0 } } END { exit !(tp > 0 && tp <= t && rp > 0 && rp <= r) }' ||
    fail "$1: p95 errors above ${2}% and ${3} deg: $line"
}

track "$S/frames" frames || fail "track on the frames exited $?: $(cat "$WORK/frames.log")"
accuracy frames 0.3 1.5
[ "$(wc -l <"$WORK/frames.jsonl")" -eq 40 ] || fail "not one line per detection"
jq -e -s 'length == 40 and ([.[].frame] == [range(40)]) and all(.[]; .id == 0 and (.R | length) == 9
  and (.t | length) == 3 and (.t[2] > 0.2 and .t[2] < 0.5) and .reprojection_error_px < 0.5
  and (keys == ["R", "frame", "id", "reprojection_error_px", "t"]))' "$WORK/frames.jsonl" >/dev/null ||
  fail "the pose lines are not as documented: $(head -2 "$WORK/frames.jsonl")"

# The same orbit through a lossy video.
track "$S/video.avi" video || fail "track on the video exited $?: $(cat "$WORK/video.log")"
accuracy video 0.5 2

# A frame without a tag and one that does not decode, among the others.
mkdir "$WORK/mixed"
cp "$S"/frames/frame_00000[0-4].png "$WORK/mixed/"
# A tag16h5 tag is no tag to a tag36h11 tracker.
"$BIN/hcosim" synth --out "$WORK/blank" --frames 1 --family tag16h5 >/dev/null 2>&1 || fail "synth of a tag16h5 frame exited $?"
cp "$WORK/blank/frames/frame_000000.png" "$WORK/mixed/frame_000002a.png"
echo "not a png" >"$WORK/mixed/frame_000003a.png"
track "$WORK/mixed" mixed || fail "track on a folder with a bad frame exited $?: $(cat "$WORK/mixed.log")"
grep -q "frame 3: no tag36h11 tag found" "$WORK/mixed.log" || fail "the frame without a tag was not named"
grep -q "frame 5: .*frame_000003a.png: cannot be read as an image, skipped" "$WORK/mixed.log" ||
  fail "the frame that does not decode was not named"
grep -q "7 frames, 5 with a tag, 5 detections .* 1 unreadable" "$WORK/mixed.log" ||
  fail "the summary does not count them: $(cat "$WORK/mixed.log")"
[ "$(jq -s -c '[.[].frame]' "$WORK/mixed.jsonl")" = "[0,1,2,4,6]" ] || fail "frames are not numbered in name order"

# expect_error CODE PATTERN ARGS...: hcosim track exits CODE and says PATTERN
expect_error() {
  local code=$1 pattern=$2
  shift 2
  "$BIN/hcosim" track "$@" >"$WORK/err.log" 2>&1
  local got=$?
  [ $got -eq "$code" ] || fail "track $* exited $got, expected $code: $(cat "$WORK/err.log")"
  grep -qE "$pattern" "$WORK/err.log" || fail "track $* did not say '$pattern': $(cat "$WORK/err.log")"
}
args=(--camera "$S/camera.yaml" --tag-size 0.05 --out "$WORK/x.jsonl")
expect_error 1 "no tag in any frame" --source "$WORK/blank/frames" "${args[@]}"
expect_error 1 "$WORK/absent: no such file or folder" --source "$WORK/absent" "${args[@]}"
echo "text" >"$WORK/fake.mp4"
expect_error 1 "fake.mp4: OpenCV cannot open it as a video" --source "$WORK/fake.mp4" "${args[@]}"
sed 's/rows: 3/rows: 2/' "$S/camera.yaml" >"$WORK/bad.yaml"
expect_error 2 "bad.yaml:[0-9]+:[0-9]+: 'camera_matrix' must be 3x3" --source "$S/frames" --camera "$WORK/bad.yaml" \
  --tag-size 0.05 --out "$WORK/x.jsonl"
sed 's/image_width: 640/image_width: 1280/; s/image_height: 480/image_height: 720/' "$S/camera.yaml" >"$WORK/hd.yaml"
expect_error 2 "calibrated at 1280x720, but the frames are 640x480" --source "$S/frames" --camera "$WORK/hd.yaml" \
  --tag-size 0.05 --out "$WORK/x.jsonl"
expect_error 2 "hcosim: --tag-size is required" --source "$S/frames" --camera "$S/camera.yaml" --out "$WORK/x.jsonl"
expect_error 2 "hcosim: --threads: Value 4e12 not in range 1 to 64" --source "$S/frames" "${args[@]}" --threads 4e12
expect_error 1 "cannot be written" --source "$S/frames" --camera "$S/camera.yaml" --tag-size 0.05 \
  --out "$WORK/absent/dir/x.jsonl"
echo "track_test: ok"

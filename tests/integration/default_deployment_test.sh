# deploy/default.yaml, what ./deploy/run.sh starts, for its first 5 s on its
# own domain: every service exits 0; the AR view writes a video of at least
# 90 frames that are not blank, with every frame registered and the objects
# covering part of it; the pictures due by then, and plots for the objects
# touched by then; the tracker's registration error against the synthetic
# camera's truth stays within 3 px at the scene's far corners (p95).
source "$(dirname "$0")/lib.sh"
from_deploy default.yaml
limit 120 "$BIN/hcosim" up "$WORK/default.yaml" --duration 5 --out "$WORK/out" >"$WORK/up.log" 2>&1 ||
  fail "up exited $?"
grep -q "lockstep run complete" "$WORK/up.log" || fail "the lockstep run did not complete"
[ "$(grep -c "exit status 0" "$WORK/up.log")" -eq "$(grep -c "started " "$WORK/up.log")" ] || fail "a service failed"
grep -q "omni: 5000 ticks" "$WORK/out/logs/omni.log" || fail "the haptic device did not run 5000 ticks"

# The video, read back by OpenCV.
"$BIN/hcosim" video "$WORK/out/ar.mp4" >"$WORK/video.log" 2>&1 || fail "hcosim video: $(cat "$WORK/video.log")"
read -r frames blank < <(sed -E 's/.*: ([0-9]+) frames, .*, ([0-9]+) blank, .*/\1 \2/' "$WORK/video.log")
[ "$frames" -ge 90 ] && [ "$blank" -eq 0 ] || fail "video: $(cat "$WORK/video.log")"
view=$WORK/out/logs/view.log
grep -qE "view: [0-9]+ frames drawn, 0 skipped \(late, or never sent\), 0 drawn with the previous frame's marker pose, 0 without" \
  "$view" || fail "frames were skipped or unregistered: $(grep 'frames drawn' "$view")"
cover=$(sed -nE 's/.*the objects cover p50 ([0-9.]+)% of a frame.*/\1/p' "$view")
awk -v c="${cover:-0}" 'BEGIN { exit !(c >= 2 && c <= 60) }' || fail "the objects cover ${cover:-no}% of a frame"

# Pictures and plots.
for f in snapshots/ar_001.1s.png snapshots/ar_002.1s.png snapshots/ar_004.7s.png plots/box.png plots/ball.png plots/all.png; do
  [ -s "$WORK/out/$f" ] || fail "no $f"
done
grep -q "5 picture(s) not taken: the run ended before 7.5 s" "$view" || fail "the pictures due later are not named"

# Registration against the synthetic truth.
reg=$(sed -nE 's/.*registration error .* p95 ([0-9.]+) px.*/\1/p' "$WORK/out/logs/cam.log")
awk -v r="${reg:-99}" 'BEGIN { exit !(r <= 3) }' || fail "registration p95 ${reg:-unknown} px"
echo "default_deployment_test: ok ($frames frames, objects cover $cover%, registration p95 $reg px)"

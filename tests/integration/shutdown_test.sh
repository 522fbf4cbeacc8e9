# SIGTERM ends a service cleanly: exit status 0, a final heartbeat, and
# its shared-memory segments removed. Runs alone (RUN_SERIAL): it compares
# /dev/shm before and after.
source "$(dirname "$0")/lib.sh"
before=$(ls /dev/shm | sort)
probe cam 30 camera
pid=${PIDS[0]}
out=$(limit 20 "$BIN/hcosim" echo CameraFrame --count 3 --timeout 15) || fail "no CameraFrame: $out"
# 640x480 bgr8 frames are larger than Fast DDS's default 512 KiB segment.
[ "$(echo "$out" | grep -c '"data_bytes":921600')" -eq 3 ] || fail "frames incomplete: $out"
during=$(ls /dev/shm | sort)
[ "$before" != "$during" ] || fail "the service created no shared-memory segment (is SHM in use?)"
kill -TERM "$pid"
wait "$pid"
code=$?
[ $code -eq 0 ] || fail "service exited $code on SIGTERM"
grep -q "probe cam: role camera" "$WORK/cam.log" || fail "no summary: the loop did not end normally"
sleep 0.5
after=$(ls /dev/shm | sort)
left=$(comm -13 <(echo "$before") <(echo "$after") | grep -v '^fastrtps_port' || true)
[ -z "$left" ] || fail "segments left in /dev/shm: $left"
echo "shutdown_test: ok"

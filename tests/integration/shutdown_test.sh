# SIGTERM ends a service cleanly: exit status 0, a final heartbeat, and
# its shared-memory segments removed. Runs alone (RUN_SERIAL): it compares
# /dev/shm before and after. A service whose stop hangs (the probe's
# stop_delay) prints its threads' stacks before hcosim up would kill it.
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

probe slow 100 source ", stop_delay: 2.5"
pid=${PIDS[1]}
sleep 1
kill -TERM "$pid"
wait "$pid" || fail "the slow probe exited $?"
log=$WORK/slow.log
grep -q "^slow: still running 1500 ms after its stop request; its threads' stacks:" "$log" ||
  fail "no stacks from a stop that hung: $(cat "$log")"
# Every thread named, the main one in the probe's main(), named thanks to
# the exported symbols.
[ "$(grep -c "^--- thread [0-9]* " "$log")" -ge 3 ] || fail "too few threads: $(cat "$log")"
sed -n '/the main thread$/,/^---/p' "$log" | grep -q "hcosim_test_probe(main+" ||
  fail "the main thread's stack does not reach main: $(cat "$log")"
echo "shutdown_test: ok"

# A stalled subscriber never blocks the 1 kHz haptic loop: with the device
# pressing the hybrid cube in real time, three readers are stopped
# (SIGSTOP) once matched, one each on a best-effort 1 kHz topic
# (HapticState), a reliable one (DeformedMesh) and all topics (a recorder);
# for the 6 s they stay stopped, the device's own status says it stepped
# on at the rate it had before (at least 90% of it, and 700 Hz), and the
# cube went on answering it.
source "$(dirname "$0")/lib.sh"
cd "$WORK"
deployment stall.yaml <<YAML
mode: realtime
duration: 28
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: press.yaml, centre: [0, 0, 0.1]}
  - name: objects
    kind: deformable
    rate: 1000
    params:
      device: omni
      visual_rate: 30
      objects:
        - {name: cube, model: hybrid, centre: [0, 0, 0.05]}
YAML
press_script 26
start status "$BIN/hcosim" echo ServiceStatus --count 0 --timeout 40
start up "$BIN/hcosim" up stall.yaml --out out
for i in $(seq 600); do grep -q "every service running" up.log && break; sleep 0.1; done
start haptic_reader "$BIN/hcosim" echo HapticState --count 0 --timeout 30
start mesh_reader "$BIN/hcosim" echo DeformedMesh --count 0 --timeout 30
start recorder "$BIN/hcosim" record all.rec --duration 30
# Stop them once they receive (discovery takes seconds on a loaded machine).
for i in $(seq 150); do [ -s haptic_reader.log ] && [ -s mesh_reader.log ] && break; sleep 0.1; done
for n in haptic_reader mesh_reader; do [ -s "$n.log" ] || fail "$n received nothing in 15 s"; done
sleep 4  # the loop's own rate, readers running, over these 4 s
for p in "${PIDS[@]:2}"; do kill -STOP "$p"; done
t0=$(date +%s%N)
sleep 6
t1=$(date +%s%N)
for p in "${PIDS[@]:2}"; do kill -CONT "$p"; kill -TERM "$p"; done
wait "${PIDS[1]}" || fail "the run exited $?: $(tail -n 20 up.log)"
wait "${PIDS[0]}"

# omni's steps per second from its status samples between two times: over
# the 4 s before the readers were stopped, and while they were.
rate() {
  jq -s --argjson a "$1" --argjson b "$2" '
    [.[] | select(.service == "omni" and .stamp.wall_time_ns >= $a and .stamp.wall_time_ns <= $b)] as $s
    | if ($s | length) < 2 then 0
      else ($s[-1].steps - $s[0].steps) / (($s[-1].stamp.wall_time_ns - $s[0].stamp.wall_time_ns) / 1e9) end' status.log
}
before=$(rate $((t0 - 4500000000)) "$t0")
during=$(rate "$t0" "$t1")
# Blocked, the loop would stop for the 6 s; under a loaded machine's own
# overruns it runs below 1 kHz either way, so the test compares.
awk -v b="$before" -v d="$during" 'BEGIN { exit !(d >= 700 && d >= 0.9 * b) }' ||
  fail "the haptic loop stepped at $during Hz while readers were stopped, $before Hz before: $(grep '"omni"' status.log | tail -n 3)"
grep -qE "cube: [0-9]+ ticks in contact" out/logs/objects.log || fail "the cube reported no contact: $(tail -n 5 out/logs/objects.log)"
contact=$(sed -nE 's/cube: ([0-9]+) ticks in contact.*/\1/p' out/logs/objects.log)
[ "$contact" -gt 15000 ] || fail "the cube answered $contact ticks in contact over 26 s of holding"
echo "stall_test: ok (haptic loop $during Hz with three readers stopped, $before Hz before; $contact ticks of contact)"

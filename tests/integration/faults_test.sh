# kill -9 of each service in turn during a real-time run of the default
# scene's services, each with on_failure: restart, recorded by hcosim up:
# each is restarted and its output is back in the recording within 2 s of
# the kill; a reliable topic's samples (a probe's HapticState on the state
# profile, numbered) are all there, in order, up to the kill; the run ends
# at its duration with exit 0, no process and no shared-memory segment of
# it left (ctest runs this test alone, so /dev/shm holds only its own).
source "$(dirname "$0")/lib.sh"
shm_before=$(shm_segments)
from_deploy default.yaml  # for its scripts
cd "$WORK"
# The default scene's services in real time, each restarted when it
# fails, on one rigid and one hybrid object with the camera and view at
# 10 Hz (the whole scene at full rate is more than two cores run in real
# time), and a probe numbering its samples.
deployment faults.yaml <<'YAML'
mode: realtime
duration: 30
scene:
  marker: {family: tag36h11, id: 0, size: 0.03}
  camera: {source: synthetic, width: 640, height: 480, sheet: 8}
  objects:
    - {name: box, kind: rigid, shape: cube, size: 0.012, mass: 0.05, centre: [-0.05, 0.035, 0.012]}
    - {name: cube, kind: deformable, model: hybrid, centre: [0.05, 0.035, 0.015], size: 0.03}
services:
  - {name: omni, kind: haptic, rate: 1000, on_failure: restart, params: {script: scripts/tour.yaml, centre: [0, 0, 0.035]}}
  - {name: bodies, kind: rigid, rate: 1000, on_failure: restart, params: {device: omni}}
  - {name: objects, kind: deformable, rate: 1000, on_failure: restart, params: {device: omni, visual_rate: 10}}
  - {name: cam, kind: tracker, rate: 10, on_failure: restart}
  - {name: view, kind: ar_view, rate: 10, on_failure: restart, params: {camera: cam, device: omni}}
  - {name: probe, kind: test_probe, rate: 100, on_failure: restart, params: {role: source, profile: state}}
YAML

start up "$BIN/hcosim" up faults.yaml --out out --record run.rec
for i in $(seq 600); do grep -q "every service running" up.log && break; sleep 0.1; done
grep -q "every service running" up.log || fail "the services did not start in 60 s: $(cat up.log)"
# Samples on every topic (and in the recording) before the first kill.
sleep 2
victims=(omni bodies objects cam view probe)
declare -A killed_at
for v in "${victims[@]}"; do
  pid=$(sed -nE "s/.*started +$v +pid ([0-9]+).*/\1/p" up.log | tail -1)
  [ -n "$pid" ] && alive "$pid" || fail "$v is not running: $(cat up.log)"
  killed_at[$v]=$(date +%s%N)
  kill -9 "$pid"
  sleep 3.5
done
wait "${PIDS[0]}" || fail "the run exited $?: $(tail -n 20 up.log)"
grep -q "duration reached" up.log || fail "the run did not reach its duration: $(tail -n 20 up.log)"
for v in "${victims[@]}"; do
  grep -q "service '$v' ended (killed by signal 9 (Killed)); restarting it (1 of 3)" up.log ||
    fail "$v was not restarted: $(cat up.log)"
done

# The first sample of each service's new process (its stamps restart from
# zero: simulated time below the old process's last) after the kill, by
# the writer's wall clock, within 2 s of it. The view publishes only its
# status.
resumed() {  # SERVICE TOPIC JQ-FILTER
  local t
  t=$("$BIN/hcosim" export run.rec --topic "$2" --wall 2>/dev/null | jq -s --argjson k "${killed_at[$1]}" "
    [.[] | select($3)] as \$all
    | ([\$all[] | select(.stamp.wall_time_ns <= \$k) | .stamp.sim_time_ns] | max) as \$old
    | [\$all[] | select(.stamp.wall_time_ns > \$k and .stamp.sim_time_ns < \$old) | .stamp.wall_time_ns] | min // empty")
  [ -n "$t" ] || fail "no $2 from $1's new process after its kill"
  local ms=$(( (t - killed_at[$1]) / 1000000 ))
  [ "$ms" -le 2000 ] || fail "$1's $2 came back $ms ms after the kill"
  echo "$1: $2 again $ms ms after kill -9" | tee -a resumed.txt
}
resumed omni HapticState '.device == "omni"'
resumed bodies RigidBodyState 'true'
resumed objects DeformedMesh '.mesh != "probe"'
resumed cam MarkerPose 'true'
resumed view ServiceStatus '.service == "view"'
resumed probe HapticState '.device == "probe"'

# Every HapticState the probe sent before its kill, numbered 0, 1, 2, ...:
# none missing up to the last one received.
"$BIN/hcosim" export run.rec --topic HapticState --wall 2>/dev/null |
  jq -r 'select(.device == "probe") | "\(.stamp.wall_time_ns) \(.seq)"' | sort -n -k1,1 |
  awk -v k="${killed_at[probe]}" '$1 < k { if (n > 0 && $2 != prev + 1) { print "gap after sample " prev ": " $2; bad = 1 } prev = $2; n++ }
    END { print n " reliable samples before the kill, none missing"; exit bad || n < 1000 }' >samples.txt ||
  fail "the probe's HapticState samples before its kill are not all recorded: $(cat samples.txt)"

for pid in $(sed -nE 's/.*pid ([0-9]+).*/\1/p' up.log); do
  alive "$pid" && fail "process $pid still running after up exited"
done
shm_after=$(shm_segments)
[ "$shm_after" -le "$shm_before" ] || fail "shared-memory segments left behind: $shm_before before, $shm_after after"
[ -z "$(domain_ports)" ] || fail "port segments of domain $DOMAIN left behind: $(domain_ports)"
cat resumed.txt
echo "faults_test: ok ($(tail -n 1 samples.txt))"

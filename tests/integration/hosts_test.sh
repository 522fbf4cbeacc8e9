# One deployment file for several hosts (docs/deployment.md, "Several
# hosts"), each host's `hcosim up FILE --host NAME` started here on one
# machine: the device on host `device`, the sheet and the cube on host
# `sim`.
# 1. Real time: the device feels the sheet served from the other host's
#    up (its report's peak force), and each up starts only its services.
# 2. Lockstep with the clock on `sim`: the run recorded on `device` exports
#    the same HapticState, ForceFeedback and DeformedMesh, bit for bit, as
#    the same file run by one `hcosim up` without --host, from step 0.
# 3. --host naming a host the file lacks is refused at the file's hosts
#    list, before anything starts.
# 4. The clock lost mid-run (killed on `sim`): the device's follower ends
#    within its 20 s wait for a tick, saying why, and its up ends with it.
source "$(dirname "$0")/lib.sh"
sheet_tour 1
body='hosts:
  - {name: device, address: 10.77.0.1}
  - {name: sim, address: 10.77.0.2, clock: on}
scene:
  objects:
    - {name: cube, kind: rigid, shape: cube, size: 0.01, mass: 0.05, centre: [-0.03, 0, 0.01]}
    - {name: sheet, kind: deformable, model: sheet, centre: [0.03, 0, 0.02], size: 0.03}
services:
  - name: omni
    kind: haptic
    rate: 1000
    host: device
    params: {script: tour.yaml, centre: [0, 0, 0.02], report: omni.json}
  - name: bodies
    kind: rigid
    rate: 1000
    host: sim
  - name: objects
    kind: deformable
    rate: 1000
    host: sim'
deployment rig.yaml <<YAML
mode: realtime
duration: 5
$body
YAML

# 1. Real time, one up per host.
start sim "$BIN/hcosim" up "$WORK/rig.yaml" --host sim --out "$WORK/rt_sim"
start device "$BIN/hcosim" up "$WORK/rig.yaml" --host device --out "$WORK/rt_device"
wait "${PIDS[0]}" || fail "up --host sim exited $?"
wait "${PIDS[1]}" || fail "up --host device exited $?"
grep -q "2 service(s) on host sim" "$WORK/sim.log" || fail "up --host sim: $(head -n 3 "$WORK/sim.log")"
grep -q "1 service(s) on host device" "$WORK/device.log" || fail "up --host device: $(head -n 3 "$WORK/device.log")"
for s in bodies objects; do [ -f "$WORK/rt_sim/logs/$s.log" ] || fail "host sim did not run $s"; done
[ -f "$WORK/rt_device/logs/omni.log" ] && [ ! -f "$WORK/rt_device/logs/objects.log" ] ||
  fail "host device ran other services: $(ls "$WORK/rt_device/logs")"
peak=$(jq -r .peak_force_n "$WORK/omni.json")
awk -v p="$peak" 'BEGIN { exit !(p > 0.02) }' || fail "the device felt $peak N of the sheet on the other host"
echo "hosts_test: real time: the device on one up felt $peak N from the sheet on another"

# 2. Lockstep: the clock on sim, the recording on device; then one up for all.
sed -e 's/^mode: realtime/mode: lockstep/' -e 's/^duration: 5/duration: 2/' "$WORK/rig.yaml" >"$WORK/ls.yaml"
start ls_sim "$BIN/hcosim" up "$WORK/ls.yaml" --host sim --out "$WORK/ls_sim"
limit 40 "$BIN/hcosim" up "$WORK/ls.yaml" --host device --record "$WORK/split.rec" --out "$WORK/ls_device" \
  >"$WORK/ls_device.log" 2>&1 || fail "lockstep up --host device exited $?"
wait "${PIDS[2]}" || fail "lockstep up --host sim exited $?"
grep -q "lockstep run complete" "$WORK/ls_sim.log" || fail "the clock's host did not complete: $(tail -n 3 "$WORK/ls_sim.log")"
grep -q "lockstep run complete (the clock runs on another host)" "$WORK/ls_device.log" ||
  fail "the device's host did not complete: $(tail -n 3 "$WORK/ls_device.log")"
limit 40 "$BIN/hcosim" up "$WORK/ls.yaml" --record "$WORK/one.rec" --out "$WORK/ls_one" >"$WORK/ls_one.log" 2>&1 ||
  fail "lockstep up on one host exited $?"
same_recordings split one
echo "hosts_test: lockstep: $(wc -l <"$WORK/HapticState.one.jsonl") states, $(wc -l <"$WORK/DeformedMesh.one.jsonl") meshes identical on two ups and on one"

# 3. A host the file lacks.
"$BIN/hcosim" up "$WORK/rig.yaml" --host camera --out "$WORK/bad" >"$WORK/bad.log" 2>&1 && fail "up --host camera ran"
grep -q "rig.yaml:[0-9]*:[0-9]*: --host camera: no such host in hosts: (device, sim)" "$WORK/bad.log" ||
  fail "the unknown host is not named at the file: $(cat "$WORK/bad.log")"
[ ! -d "$WORK/bad/logs" ] || [ -z "$(ls "$WORK/bad/logs")" ] || fail "up --host camera started something"

# 4. The clock's host lost: its clock killed once the run is under way.
sed -e 's/^duration: 2/duration: 600/' "$WORK/ls.yaml" >"$WORK/lost.yaml"
start lost_sim "$BIN/hcosim" up "$WORK/lost.yaml" --host sim --out "$WORK/lost_sim"
start lost_device "$BIN/hcosim" up "$WORK/lost.yaml" --host device --out "$WORK/lost_device"
limit 60 "$BIN/hcosim" echo ClockTick --count 100 --domain "$DOMAIN" >"$WORK/ticks.jsonl" 2>&1 ||
  fail "no lockstep run under way: $(tail -n 1 "$WORK/ticks.jsonl")"
clock=$(sed -nE 's/.*started +clock +pid ([0-9]+).*/\1/p' "$WORK/lost_sim.log")
[ -n "$clock" ] || fail "no clock on host sim: $(cat "$WORK/lost_sim.log")"
kill -KILL "$clock"
t0=$(date +%s)
for _ in $(seq $((400 * SLOWDOWN))); do alive "${PIDS[4]}" || break; sleep 0.1; done
alive "${PIDS[4]}" && fail "the device's up still runs $(($(date +%s) - t0)) s after the clock was killed"
wait "${PIDS[4]}"
code=$?
[ $code -ne 0 ] || fail "the device's up exited 0 with the clock gone"
waited=$(($(date +%s) - t0))
# The follower says the clock is gone, or, where the clock was killed
# between sending a step's tick to this host and to the sim's, that the
# objects on the sim's host never answered that step, whose 10 s limit
# comes before the clock's 20 s: either names a peer lost.
grep -qE "omni: (no tick from the clock for 20 s after step [0-9]*; the clock stopped or its host is gone|step [0-9]*: the sources of its group did not answer in 10 s)" \
  "$WORK/lost_device/logs/omni.log" || fail "the follower did not say it lost the clock: $(tail -n 3 "$WORK/lost_device/logs/omni.log")"
grep -q "service 'omni' ended (exit status 1)" "$WORK/lost_device.log" ||
  fail "the device's up did not name its follower's end: $(tail -n 3 "$WORK/lost_device.log")"
wait "${PIDS[3]}"
echo "hosts_test: clock lost: the device's up ended $waited s after (exit $code), its follower saying why"
echo "hosts_test: ok"

# The deformable service in a real deployment: the virtual user presses the
# hybrid cube through the simulated Omni while a sheet waits untouched
# beside it; a probe sends NaN haptic states, which must be refused and
# counted. Meshes reach a subscriber; a late subscriber still gets both
# topologies.
source "$(dirname "$0")/lib.sh"
press_script 6
deployment up.yaml <<'YAML'
mode: realtime
duration: 8
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: press.yaml, centre: [0, 0, 0.1], answer_wait: 0.0005}
  - name: objs
    kind: deformable
    rate: 1000
    params:
      device: omni
      visual_rate: 30
      objects:
        - {name: cube, model: hybrid, centre: [0, 0, 0.05]}
        - {name: sheet, model: sheet, centre: [0.3, 0, 0], resolution: 21}
  - name: bad
    kind: test_probe
    rate: 200
    params: {role: source, nan_every: 2}
YAML
start mesh "$BIN/hcosim" echo DeformedMesh --count 20 --timeout 12
start status "$BIN/hcosim" echo ServiceStatus --count 0 --timeout 12
(sleep 4 && exec "$BIN/hcosim" echo DeformedMeshTopology --count 2 --timeout 7 >"$WORK/late.log" 2>&1) &
PIDS+=($!)
limit 40 "$BIN/hcosim" up "$WORK/up.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?"
wait "${PIDS[0]}" || fail "fewer than 20 meshes reached the subscriber"
wait "${PIDS[2]}" || fail "the late subscriber did not receive both topologies"
log="$WORK/out/logs/objs.log"
cube=$(grep "cube:.*ticks in contact" "$log") || fail "no summary for the cube"
contact=$(echo "$cube" | sed -nE 's/cube: ([0-9]+) ticks in contact.*/\1/p')
[ "${contact:-0}" -gt 1000 ] || fail "the cube was touched for only ${contact:-0} ticks: $cube"
# The stylus sticks where the hand's pull exceeds the cube's push by up to
# the Omni's back-drive friction (0.1 N).
echo "$cube" | awk '{ for (i = 1; i <= NF; i++) if ($i == "force") f = $(i + 1) } END { exit !(f > 0.1 && f < 3) }' ||
  fail "max force on the cube outside 0.1..3 N: $cube"
grep -q "sheet: 0 ticks in contact" "$log" || fail "the untouched sheet reports contact: $(grep sheet: "$log")"
grep -q '"mesh":"cube"' "$WORK/mesh.log" || fail "no cube mesh on the wire"
grep -q '"mesh":"sheet"' "$WORK/mesh.log" || fail "no sheet mesh on the wire: every object is published each frame"
n=$(grep -m1 '"mesh":"cube"' "$WORK/mesh.log" | grep -oE '"positions":\[[^]]*\]' | tr ',' '\n' | wc -l)
[ "$n" -eq 16206 ] || fail "a cube mesh carries $n coordinates, not 3 x 5402"
grep -q '"vertex_count":5402' "$WORK/late.log" || fail "late subscriber: no cube topology"
grep -q '"vertex_count":441' "$WORK/late.log" || fail "late subscriber: no sheet topology"
grep -E '"service":"objs"' "$WORK/status.log" | grep -qE '"samples_rejected":[1-9]' ||
  fail "NaN haptic states were not counted as rejected by objs"
answered=$(sed -nE 's/.* ([0-9]+) answered.*/\1/p' "$WORK/out/logs/omni.log")
[ "${answered:-0}" -gt 1000 ] || fail "only ${answered:-0} haptic states answered"
echo "deformable_test: ok"

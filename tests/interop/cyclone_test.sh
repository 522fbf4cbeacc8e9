# A Cyclone DDS participant joins a running hcosim service late and still
# rebuilds complete meshes: topology from the latched topic, positions from
# DeformedMesh (5402 vertices, the seed's visual mesh size); first from a
# probe writing known values, then from the deformable service's hybrid
# cube, with one reader there from the start and one joining late.
# usage: bash cyclone_test.sh BIN_DIR TEST_BIN_DIR DOMAIN READER
source "$(dirname "$0")/../integration/lib.sh"
READER=$4
probe liver 30 mesh ", vertices: 5402"
sleep 2  # the topology was written before the reader existed
out=$(limit 60 "$READER" "$DOMAIN" 5402 5 40 2>&1) || fail "cyclone reader: $out"
echo "$out"
echo "$out" | grep -q "topology of 'liver', version 1, 5402 vertices, 5400 triangles" || fail "topology: $out"

# The real deformable service in a deployment: one Cyclone reader is there
# before it starts (live), another joins 2 s later (late); both rebuild the
# hybrid cube's 5402-vertex visual mesh.
kill -TERM "${PIDS[0]}" && wait "${PIDS[0]}"  # the probe's meshes end here
cube_alone cube.yaml 8
"$READER" "$DOMAIN" 5402 10 30 model >"$WORK/live.log" 2>&1 &
live=$!
PIDS+=($live)
start up "$BIN/hcosim" up "$WORK/cube.yaml" --out "$WORK/out"
sleep 2
out=$(limit 30 "$READER" "$DOMAIN" 5402 10 20 model 2>&1) || fail "late cyclone reader: $out"
echo "late: $out"
echo "$out" | grep -q "topology of 'cube', version 1, 5402 vertices" || fail "late topology: $out"
wait $live || fail "live cyclone reader: $(cat "$WORK/live.log")"
echo "live: $(cat "$WORK/live.log")"
grep -q "topology of 'cube', version 1, 5402 vertices" "$WORK/live.log" || fail "live topology: $(cat "$WORK/live.log")"
echo "cyclone_test: ok"

# A Cyclone DDS participant joins a running hcosim service late and still
# rebuilds complete meshes: topology from the latched topic, positions from
# DeformedMesh (5402 vertices, the seed's visual mesh size).
# usage: bash cyclone_test.sh BIN_DIR TEST_BIN_DIR DOMAIN READER
source "$(dirname "$0")/../integration/lib.sh"
READER=$4
probe liver 30 mesh ", vertices: 5402"
sleep 2  # the topology was written before the reader existed
out=$(timeout 60 "$READER" "$DOMAIN" 5402 5 40 2>&1) || fail "cyclone reader: $out"
echo "$out"
echo "$out" | grep -q "topology of 'liver', version 1, 5402 vertices, 5400 triangles" || fail "topology: $out"
echo "cyclone_test: ok"

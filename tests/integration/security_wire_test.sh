# DDS Security on the wire: the same run captured on loopback (tshark)
# without and with security, shared memory off and UDP bound to 127.0.0.1
# (deploy/qos.xml otherwise). Without it the mesh's name and the topic's
# name are on the wire in plain text; with it neither is, while secure RTPS
# messages do flow. Skipped (77) when tshark cannot capture on lo here.
source "$(dirname "$0")/lib.sh"
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$WORK"
command -v tshark >/dev/null || { echo "SKIP: no tshark (deploy/setup.sh installs it)"; exit 77; }
if ! timeout 60 tshark -i lo -a duration:1 -w probe.pcap -q >probe.log 2>&1; then
  grep -qiE "permission|not permitted|could not be initiated" probe.log &&
    { echo "SKIP: tshark may not capture on lo here: $(tail -n 2 probe.log)"; exit 77; }
  fail "tshark failed to capture on lo: $(tail -n 5 probe.log)"
fi

# UDP only, on 127.0.0.1: no SHM transport, so every sample crosses lo.
sed -e '/<userTransports>/,/<\/userTransports>/{/hcosim_shm/d}' \
    -e 's#<type>UDPv4</type>#&<interfaceWhiteList><address>127.0.0.1</address></interfaceWhiteList>#' \
    "$ROOT/deploy/qos.xml" >udp.xml
grep -q "hcosim_shm</transport_id>" udp.xml && ! sed -n '/<userTransports>/,/<\/userTransports>/p' udp.xml | grep -q shm ||
  fail "could not take shared memory out of the participant's transports"
export HCOSIM_QOS=$WORK/udp.xml

# A mesh named so that it cannot appear by chance.
cube_alone plain.yaml 6 wiremarker
{ echo "security: {dir: keys}"; cat plain.yaml; } >secure.yaml
"$BIN/hcosim" security init --deployment secure.yaml >init.log 2>&1 || fail "security init exited $?"

# This domain's ports only: 7400 + 250 * domain and the 250 after it.
base=$((7400 + 250 * DOMAIN))
capture() {  # NAME FILE [echo's security flags]
  local name=$1 file=$2
  shift 2
  tshark -i lo -f "udp portrange $base-$((base + 249))" -w "$name.pcap" -a duration:11 -q >"$name.tshark" 2>&1 &
  local cap=$!
  sleep 2
  "$BIN/hcosim" up "$file" --out "out_$name" >"$name.up" 2>&1 &
  local up=$!
  sleep 1
  "$BIN/hcosim" echo DeformedMesh --count 3 --timeout 6 "$@" >"$name.echo" 2>&1
  wait $up || fail "$name run exited $?"
  wait $cap
  [ "$(grep -c '^{"mesh":"wiremarker"' "$name.echo")" -eq 3 ] || fail "$name: the reader got no meshes: $(tail -n 3 "$name.echo")"
}
capture plain plain.yaml
capture secure secure.yaml --security keys

rtps() { tshark -r "$1.pcap" -Y "$2" 2>/dev/null | wc -l; }
[ "$(rtps plain rtps)" -gt 0 ] || fail "no RTPS captured in the plain run: $(cat plain.tshark)"
grep -a -q wiremarker plain.pcap || fail "the plain run's mesh name is not on the wire: the capture sees no payloads"
grep -a -q DeformedMesh plain.pcap || fail "the plain run's topic name is not on the wire"
n=$(rtps secure 'rtps.sm.id == 0x30 || rtps.sm.id == 0x31 || rtps.sm.id == 0x33')
[ "$n" -gt 0 ] || fail "no secure RTPS submessages captured in the secure run"
! grep -a -q wiremarker secure.pcap || fail "the secure run's mesh name is on the wire in plain text"
! grep -a -q DeformedMesh secure.pcap || fail "the secure run's topic name is on the wire in plain text"
echo "security_wire_test: ok ($n secure RTPS packets, $(rtps plain rtps) plain)"

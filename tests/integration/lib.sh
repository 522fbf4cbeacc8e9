# Shared by the integration tests. ctest runs each script as
#   bash SCRIPT BIN_DIR TEST_BIN_DIR DOMAIN
# with a domain id of its own, so tests can run in parallel.
set -u
BIN=$1
export HCOSIM_SERVICE_PATH=$2
DOMAIN=$3
export HCOSIM_DOMAIN=$DOMAIN
# One folder of hybrid objects' visual maps and force gains for every test
# of this build (HCOSIM_CACHE, services/deformable): integration.hybrid_cache,
# a fixture the others require, fills it with the default and press scenes'
# objects; the others read those, as a user's second run does (and compute
# the maps of objects placed elsewhere).
export HCOSIM_CACHE=${HCOSIM_CACHE:-$(dirname "$BIN")/test-cache}
WORK=$(mktemp -d /tmp/hcosim_it.XXXXXX)
PIDS=()

cleanup() {
  for p in "${PIDS[@]}"; do kill -TERM "$p" 2>/dev/null; done
  for p in "${PIDS[@]}"; do wait "$p" 2>/dev/null; done
  # HCOSIM_KEEP_WORK=1 keeps the work folder for a look after a failure.
  [ -n "${HCOSIM_KEEP_WORK:-}" ] && echo "kept $WORK" >&2 || rm -rf "$WORK"
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*" >&2
  for f in "$WORK"/*.log "$WORK"/*/logs/*.log; do
    [ -f "$f" ] || continue
    echo "--- $f" >&2
    # A stop that hung: where the main thread was (runtime/service.cc).
    grep -q "still running .* after its stop request" "$f" &&
      sed -n '/still running .* after its stop request/,/the main thread$/p; /the main thread$/,/^--- thread/p' "$f" >&2
    tail -n 20 "$f" >&2
  done
  exit 1
}

# limit SECONDS COMMAND...: runs a command, killed after SECONDS, scaled by
# the build's slowdown (3 under sanitizers, tests/CMakeLists.txt)
SLOWDOWN=${HCOSIM_TEST_SLOWDOWN:-1}
limit() {
  local s=$1
  shift
  timeout $((s * SLOWDOWN)) "$@"
}

# start NAME COMMAND...: runs a command in the background, output to $WORK/NAME.log
start() {
  local name=$1
  shift
  "$@" >"$WORK/$name.log" 2>&1 &
  PIDS+=($!)
}

# stop_echoes PID...: once a deployment has ended, lets `hcosim echo`
# processes started with --count 0 and no --timeout (or `hcosim record` with
# --duration 0) write what they have taken, then stops each with SIGINT (a
# clean end for both); fails if one does not end cleanly.
stop_echoes() {
  local p
  sleep 0.5
  for p in "$@"; do kill -INT "$p" 2>/dev/null; done
  for p in "$@"; do wait "$p" || fail "an echo or recorder exited $? on SIGINT"; done
}

# probe NAME RATE ROLE [extra yaml params]: a test service on $DOMAIN in real time
probe() {
  local name=$1 rate=$2 role=$3 extra=${4:-}
  cat >"$WORK/$name.yaml" <<YAML
services:
  - name: $name
    kind: test_probe
    rate: $rate
    params: {role: $role $extra}
YAML
  start "$name" "$HCOSIM_SERVICE_PATH/hcosim_test_probe" --name "$name" --rate "$rate" --domain "$DOMAIN" \
    --deployment "$WORK/$name.yaml"
}

# deployment FILE: writes stdin to $WORK/FILE with the test's domain
deployment() {
  { echo "domain: $DOMAIN"; cat; } >"$WORK/$1"
}

# from_deploy FILE: deploy/FILE, with its scripts and meshes, into $WORK on the test's domain
from_deploy() {
  local root
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
  cp -r "$root/deploy/scripts" "$root/deploy/meshes" "$WORK/"
  sed -E "s/^domain: .*/domain: $DOMAIN/" "$root/deploy/$1" >"$WORK/$1"
  grep -q "^domain: $DOMAIN$" "$WORK/$1" || fail "deploy/$1 has no top-level domain line to override"
}

alive() { kill -0 "$1" 2>/dev/null; }

# cube_alone FILE DURATION [NAME]: the default deployment's hybrid cube
# (named NAME, else cube) served alone by a deformable service in real time
# for DURATION s, into $WORK/FILE
cube_alone() {
  deployment "$1" <<YAML
mode: realtime
duration: $2
services:
  - name: objects
    kind: deformable
    rate: 1000
    params:
      device: omni
      objects:
        - {name: ${3:-cube}, model: hybrid, centre: [0, 0, 0.05], size: 0.1}
YAML
}

# press_script HOLD: $WORK/press.yaml, the virtual user pressing the top of
# the hybrid cube centred at [0, 0, 0.05] (device centre [0, 0, 0.1]) 8 mm
# deep, then holding there for HOLD s
press_script() {
  cat >"$WORK/press.yaml" <<YAML
start: [0, 0, 0.12]
actions:
  - move_to: {to: [0, 0, 0.102], speed: 0.05}
  - press: {depth: 0.008, speed: 0.01}
  - hold: {duration: $1}
YAML
}

# sheet_tour HOLD [FILE [TO DEPTH]]: $WORK/FILE (tour.yaml), the virtual
# user moving from above the middle to a sheet centred at [0.03, 0, 0.02]
# (device centre [0, 0, 0.02]), pressing it 8 mm deep, holding HOLD s, and
# waiting above it; or to TO (as [x, y, z]), pressing DEPTH m
sheet_tour() {
  cat >"$WORK/${2:-tour.yaml}" <<YAML
start: [0, 0, 0.05]
actions:
  - move_to: {to: ${3:-[0.03, 0, 0.024]}, speed: 0.05}
  - press: {depth: ${4:-0.008}, speed: 0.01}
  - hold: {duration: $1}
  - release: {speed: 0.02}
  - hold: {duration: 20}
YAML
}

# same_recordings SPLIT ONE [TOPIC...]: fails unless the recordings
# $WORK/SPLIT.rec and $WORK/ONE.rec export the same HapticState,
# ForceFeedback, DeformedMesh and TOPICs, bit for bit, each from step 0
# (every writer reaches the recording before its first step:
# runtime/recordings.h), and the stylus touched something; leaves
# $WORK/TOPIC.ONE.jsonl. MarkerPose's latency_ms, a wall-clock
# measurement, is left out.
same_recordings() {
  local t run first split=$1 one=$2
  shift 2
  for t in HapticState ForceFeedback DeformedMesh "$@"; do
    for run in "$split" "$one"; do
      "$BIN/hcosim" export "$WORK/$run.rec" --topic $t >"$WORK/$t.$run.raw" 2>/dev/null || fail "export $t of $run"
      sed -E 's/,"latency_ms":[^,}]*//' "$WORK/$t.$run.raw" >"$WORK/$t.$run.jsonl"
      first=$(head -n 1 "$WORK/$t.$run.jsonl" | grep -oE '"step":[0-9]+' | head -n 1)
      [ "$first" = '"step":0' ] || fail "$run.rec's first $t is not of step 0 but ${first:-none}"
    done
    cmp -s "$WORK/$t.$split.jsonl" "$WORK/$t.$one.jsonl" ||
      fail "$t differs between $split.rec and $one.rec from line $(cmp "$WORK/$t.$split.jsonl" "$WORK/$t.$one.jsonl" | awk '{ print $NF }')"
  done
  grep -q '"in_contact":true' "$WORK/ForceFeedback.$one.jsonl" || fail "the lockstep run never touched anything"
}

# shm_segments: Fast DDS's shared-memory segments in /dev/shm (data and
# ports), not the 32-byte named semaphores it leaves for every port number
# ever used (sem.fastrtps_portN_mutex, which `fastdds shm clean` leaves too)
shm_segments() { ls /dev/shm | grep '^fastrtps_' | wc -l; }
# domain_ports: the port segments of $DOMAIN's participants (unicast ports
# 7400 + 250 * domain + 10 + 2 * id and + 1, ids 0 to 119) left in /dev/shm
domain_ports() {
  local first=$((7400 + 250 * DOMAIN + 10))
  ls /dev/shm | sed -nE 's/^fastrtps_port([0-9]+)$/\1/p' | awk -v f="$first" '$1 >= f && $1 < f + 240' | tr '\n' ' '
}

# running_then_bare LOG SECONDS: once LOG says every service runs, a bare
# Fast DDS ping-pong pair at the haptic threads' priority for SECONDS on
# the next domain (tests/CMakeLists.txt keeps it free), beside the
# deployment: the machine's own real-time baseline, same time, same load.
# Sets BARE to its share of round trips within 0.8 ms (the device's wait).
running_then_bare() {
  local log=$1 seconds=$2
  for _ in $(seq 600); do
    grep -q "every service running" "$log" && break
    sleep 0.1
  done
  grep -q "every service running" "$log" || fail "the deployment never ran: $(cat "$log")"
  "$BIN/hcosim" bench-peer --impl bare --role ping --domain $((DOMAIN + 1)) --duration "$seconds" --priority 30 \
    >"$WORK/bare.log" 2>&1 || fail "the bare pair: $(cat "$WORK/bare.log")"
  BARE=$(tail -n 1 "$WORK/bare.log" | jq -r .within_0_8ms_ratio) || fail "the bare pair: $(cat "$WORK/bare.log")"
}

# within_bare RATIO [MARGIN]: whether a loop's share of ticks answered in
# time is at least 0.99, or where bare Fast DDS beside it got less than
# 0.99 + MARGIN, at least BARE less MARGIN (default 0.01).
within_bare() {
  awk -v r="$1" -v b="$BARE" -v m="${2:-0.01}" 'BEGIN { bound = b - m < 0.99 ? b - m : 0.99; exit !(r >= bound) }'
}

# Hosts made of Linux network namespaces (integration.network,
# integration.rig): make_hosts NAME... makes one namespace per NAME, each
# with a veth on one bridge and the address $NET.1, $NET.2, ... in that
# order, or exits 77 (skipped, saying why) where this machine cannot;
# everything it makes goes at exit. on_host HOST COMMAND... runs COMMAND
# in HOST's namespace with a /dev/shm of HOST's own.
HOSTS=()
TAG=$((DOMAIN % 1000))
BRIDGE=hcbr$TAG
NET=10.$((100 + DOMAIN % 100)).0
ns_of() { echo "hc${TAG}$1"; }
# What make_hosts made, with what runs inside; also a killed run's left-overs.
hosts_down() {
  local h p
  for h in "${HOSTS[@]}" probe; do
    for p in $(ip netns pids "$(ns_of "$h")" 2>/dev/null); do kill -KILL "$p" 2>/dev/null; done
    ip netns del "$(ns_of "$h")" 2>/dev/null
  done
  ip link del "$BRIDGE" 2>/dev/null
}
# Whether this machine lets a test make hosts: a namespace, a veth pair and
# a bridge, and a folder mounted as a namespace's /dev/shm.
can_make_hosts() {
  [ "$(id -u)" = 0 ] && command -v ip >/dev/null && command -v bridge >/dev/null &&
    ip netns add "$(ns_of probe)" && ip link add "$BRIDGE" type bridge &&
    ip link add "$(ns_of probe)" type veth peer name eth0 netns "$(ns_of probe)" &&
    mkdir -p "$WORK/shm_probe" &&
    ip netns exec "$(ns_of probe)" sh -c 'mount --bind "$0" /dev/shm' "$WORK/shm_probe"
}
make_hosts() {
  local test h ns i=0
  test=$(basename "$0" .sh)
  HOSTS=("$@")
  trap 'hosts_down; cleanup' EXIT
  hosts_down
  if ! can_make_hosts >"$WORK/can.log" 2>&1; then
    echo "$test: SKIPPED: cannot make network namespaces here (needs root, iproute2's ip and bridge," \
      "veth and bridge links, and mounts): $(tail -n 1 "$WORK/can.log")"
    exit 77
  fi
  hosts_down
  ip link add "$BRIDGE" type bridge && ip link set "$BRIDGE" up || fail "cannot make bridge $BRIDGE"
  for h in "$@"; do
    i=$((i + 1))
    ns=$(ns_of "$h")
    ip netns add "$ns" && ip link add "$ns" type veth peer name eth0 netns "$ns" &&
      ip link set "$ns" master "$BRIDGE" up && ip netns exec "$ns" ip addr add "$NET.$i/24" dev eth0 &&
      ip netns exec "$ns" ip link set eth0 up && ip netns exec "$ns" ip link set lo up || fail "cannot make host $h"
  done
}
on_host() {
  local h=$1
  shift
  mkdir -p "$WORK/shm_$h"
  ip netns exec "$(ns_of "$h")" sh -c 'mount --bind "$0" /dev/shm && exec "$@"' "$WORK/shm_$h" "$@"
}

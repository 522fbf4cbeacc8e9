# Shared by the integration tests. ctest runs each script as
#   bash SCRIPT BIN_DIR TEST_BIN_DIR DOMAIN
# with a domain id of its own, so tests can run in parallel.
set -u
BIN=$1
export HCOSIM_SERVICE_PATH=$2
DOMAIN=$3
export HCOSIM_DOMAIN=$DOMAIN
# One folder of hybrid objects' visual maps and force gains for every test
# of this build (HCOSIM_CACHE, services/deformable): the first test to need
# one computes it, the others read it, as a user's second run does.
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
    [ -f "$f" ] && { echo "--- $f" >&2; tail -n 20 "$f" >&2; }
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

# same_from_step_200 SPLIT ONE: fails unless the recordings $WORK/SPLIT.rec
# and $WORK/ONE.rec export the same HapticState, ForceFeedback and
# DeformedMesh, bit for bit, from step 200 on (a lockstep recording may
# miss a writer's first steps, matched after the clock started: an open
# defect of --record), and the press reached the sheet; leaves
# $WORK/TOPIC.ONE.jsonl
same_from_step_200() {
  local t run
  for t in HapticState ForceFeedback DeformedMesh; do
    for run in "$1" "$2"; do
      "$BIN/hcosim" export "$WORK/$run.rec" --topic $t 2>/dev/null | grep -vE '"step":(1?[0-9]?[0-9]),' \
        >"$WORK/$t.$run.jsonl" || fail "export $t of $run: nothing from step 200 on"
    done
    cmp -s "$WORK/$t.$1.jsonl" "$WORK/$t.$2.jsonl" ||
      fail "$t differs between $1.rec and $2.rec from line $(cmp "$WORK/$t.$1.jsonl" "$WORK/$t.$2.jsonl" | awk '{ print $NF }')"
  done
  grep -q '"in_contact":true' "$WORK/ForceFeedback.$2.jsonl" || fail "the lockstep press never reached the sheet"
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

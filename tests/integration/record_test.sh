# Recordings: hcosim up --record keeps every sample of a lockstep run of
# deploy/press.yaml, and hcosim export prints one topic of it in step
# order, as JSON lines without wall-clock fields or as CSV; hcosim record
# FILE --topics records chosen topics from a running deployment. Unknown
# topics, files that are not recordings and cut-short recordings are named.
source "$(dirname "$0")/lib.sh"
from_deploy press.yaml
limit 60 "$BIN/hcosim" up "$WORK/press.yaml" --duration 0.5 --record "$WORK/run.rec" --out "$WORK/out" \
  >"$WORK/up.log" 2>&1 || fail "up exited $?"
grep -qE "recorded [0-9]+ samples to $WORK/run.rec" "$WORK/up.log" || fail "up did not say what it recorded"

"$BIN/hcosim" export "$WORK/run.rec" --topic HapticState >"$WORK/state.jsonl" 2>"$WORK/export.log" ||
  fail "export exited $?: $(cat "$WORK/export.log")"
# Every one of the 500 steps' states, in step order, without wall time.
jq -e -s 'length == 500 and ([.[].stamp.step] == [range(500)]) and all(.[]; .device == "omni" and
  (.stamp | has("wall_time_ns") | not))' "$WORK/state.jsonl" >/dev/null ||
  fail "HapticState export is not the 500 steps in order: $(head -c 300 "$WORK/state.jsonl")"
"$BIN/hcosim" export "$WORK/run.rec" --topic HapticState --wall | head -1 | grep -q '"wall_time_ns":' ||
  fail "--wall does not keep wall time"
n=$("$BIN/hcosim" export "$WORK/run.rec" --topic DeformedMesh 2>/dev/null | jq -s 'map(.positions | length) | unique')
[ "$n" = "$(printf '[\n  16206\n]')" ] || fail "DeformedMesh samples are not whole 5402-vertex meshes: $n"
"$BIN/hcosim" export "$WORK/run.rec" --topic HapticState --format csv >"$WORK/state.csv" 2>/dev/null ||
  fail "csv export exited $?"
head -1 "$WORK/state.csv" | grep -q "^device,seq,stamp.step,stamp.sim_time_ns,device_time_s,position.x," ||
  fail "csv header: $(head -1 "$WORK/state.csv")"
[ "$(wc -l <"$WORK/state.csv")" -eq 501 ] || fail "csv is not a header and 500 rows"
sed -n 2p "$WORK/state.csv" | grep -q "^omni,0,0,0," || fail "csv first row: $(sed -n 2p "$WORK/state.csv")"

# Chosen topics from a running deployment.
deployment up.yaml <<'YAML'
mode: realtime
duration: 3
services:
  - {name: src, kind: test_probe, rate: 200, params: {role: source}}
  - {name: wall, kind: test_probe, rate: 200, params: {role: wall}}
YAML
# It records until the deployment has ended, not for a fixed time that a
# slow start can use up, cutting off the run's end.
start rec "$BIN/hcosim" record "$WORK/probe.rec" --topics ForceFeedback,ServiceStatus --duration 0
limit 30 "$BIN/hcosim" up "$WORK/up.yaml" --out "$WORK/out2" >"$WORK/up2.log" 2>&1 || fail "up exited $?"
stop_echoes "${PIDS[0]}"
forces=$("$BIN/hcosim" export "$WORK/probe.rec" --topic ForceFeedback 2>/dev/null | wc -l)
[ "$forces" -gt 300 ] || fail "only $forces ForceFeedback samples recorded"
[ "$("$BIN/hcosim" export "$WORK/probe.rec" --topic HapticState 2>/dev/null | wc -l)" -eq 0 ] ||
  fail "an unchosen topic was recorded"
"$BIN/hcosim" export "$WORK/probe.rec" --topic ServiceStatus 2>/dev/null | grep -q '"service":"wall"' ||
  fail "no ServiceStatus recorded"

# A recorder that falls behind says what it never received: stopped for
# 2.5 s while a probe sends 1000 HapticState samples a second (more than
# a shared-memory port queues, 1024), it reports as lost exactly as many
# samples as the probe's numbering misses in its recording. So on the
# best-effort profile (control) and on the reliable one (state), whose
# writer keeps only its last 16 samples to repair a loss with. The
# recorder must have matched the probe before it is stopped: under
# sanitizers and a parallel test it can take more than 2 s to start.
# Each recording lasts that wait, the 2.5 s stop and 1.5 s more.
lost_report=""
for profile in control state; do
  probe "fast_$profile" 1000 source ", profile: $profile"
  source_pid=${PIDS[-1]}
  start "rec_$profile" "$BIN/hcosim" record "$WORK/$profile.rec" --topics HapticState --duration $((2 * SLOWDOWN + 4))
  rec=${PIDS[-1]}
  sleep $((2 * SLOWDOWN))
  kill -STOP "$rec"
  sleep 2.5
  kill -CONT "$rec"
  wait "$rec" || fail "record exited $?: $(cat "$WORK/rec_$profile.log")"
  kill "$source_pid"
  wait "$source_pid"
  lost=$(sed -nE 's/.*never received: HapticState ([0-9]+)$/\1/p' "$WORK/rec_$profile.log")
  missing=$("$BIN/hcosim" export "$WORK/$profile.rec" --topic HapticState 2>/dev/null |
    jq -r .seq | awk 'NR == 1 { first = $1 } { n++; last = $1 } END { print last - first + 1 - n }')
  [ "${lost:-0}" -gt 0 ] && [ "$lost" -eq "$missing" ] ||
    fail "$profile: record reported ${lost:-no} samples lost, the recording misses $missing: $(cat "$WORK/rec_$profile.log")"
  lost_report+=" $profile $lost,"
done

# A recorder whose file stalls loses nothing: the recording goes through a
# pipe whose reader is stopped for 2.5 s (a disk that falls behind), while
# the probe sends 1000 reliable samples a second. The recorder keeps
# receiving while its file waits, so its recording has every sample.
probe fast_stall 1000 source ", profile: state"
source_pid=${PIDS[-1]}
mkfifo "$WORK/stall.fifo"
cat "$WORK/stall.fifo" >"$WORK/stall.rec" &
PIDS+=($!)
drain=$!
start rec_stall "$BIN/hcosim" record "$WORK/stall.fifo" --topics HapticState --duration $((2 * SLOWDOWN + 4))
rec=${PIDS[-1]}
sleep $((2 * SLOWDOWN))
kill -STOP "$drain"
sleep 2.5
kill -CONT "$drain"
wait "$rec" || fail "record exited $?: $(cat "$WORK/rec_stall.log")"
kill "$source_pid"
wait "$source_pid"
wait "$drain"
! grep -q "never received" "$WORK/rec_stall.log" ||
  fail "a stalled file lost samples: $(cat "$WORK/rec_stall.log")"
"$BIN/hcosim" export "$WORK/stall.rec" --topic HapticState 2>/dev/null | jq -r .seq |
  awk 'NR > 1 && $1 != prev + 1 { print "gap after " prev ": " $1; bad = 1 } { prev = $1; n++ }
    END { print n " samples"; exit bad || n < 3000 }' >"$WORK/stall.txt" ||
  fail "the recording through a stalled file misses samples: $(cat "$WORK/stall.txt")"

# Errors.
expect() {  # CODE PATTERN COMMAND...
  local code=$1 pattern=$2
  shift 2
  "$@" >"$WORK/err.log" 2>&1
  local got=$?
  [ $got -eq "$code" ] || fail "$* exited $got, expected $code: $(cat "$WORK/err.log")"
  grep -qE -- "$pattern" "$WORK/err.log" || fail "$* did not say '$pattern': $(cat "$WORK/err.log")"
}
expect 2 "unknown topic 'Nope'" "$BIN/hcosim" export "$WORK/run.rec" --topic Nope
expect 2 "unknown topic 'Nope'" "$BIN/hcosim" record "$WORK/x.rec" --topics Nope --duration 1
expect 1 "up.yaml: not an hcosim recording" "$BIN/hcosim" export "$WORK/up.yaml" --topic HapticState
head -c 100000 "$WORK/run.rec" >"$WORK/cut.rec"
expect 1 "cut.rec: record at byte [0-9]+ is cut short" "$BIN/hcosim" export "$WORK/cut.rec" --topic HapticState
expect 2 "--format: xml not in \{jsonl,csv\}" "$BIN/hcosim" export "$WORK/run.rec" --topic HapticState --format xml
echo "record_test: ok (lost while the recorder was stopped, all reported:${lost_report%,}; through a stalled file: $(cat "$WORK/stall.txt"), none lost)"

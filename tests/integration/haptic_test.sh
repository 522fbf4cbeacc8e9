# The haptic service in a real deployment: the virtual user presses the
# simulated Omni into a wall served by another process over Fast DDS; the
# stylus settles at the depth where hand and wall balance, the device never
# outputs more than 3.3 N, and the service reports the round trip. Then
# `hcosim record` captures the stylus, and a replay device plays it back.
source "$(dirname "$0")/lib.sh"
cat >"$WORK/press.yaml" <<'YAML'
start: [0, 0, 0.01]
actions:
  - press: {depth: 0.02, speed: 0.02}
  - hold: {duration: 3}
YAML
deployment up.yaml <<'YAML'
mode: realtime
duration: 4
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: press.yaml}
  - name: wall
    kind: test_probe
    rate: 1000
    priority: 30  # a force source, as the rigid and deformable kinds are by default
    params: {role: wall, stiffness: 500, nan_every: 50}
YAML
# The echoes and the recorder listen until the deployment has ended
# (stop_echoes), not to a deadline that a slow start on a loaded machine can
# reach first, cutting off the run's end.
start state "$BIN/hcosim" echo HapticState --count 0
start status "$BIN/hcosim" echo ServiceStatus --count 0
start record "$BIN/hcosim" record --device omni --duration 0 --out "$WORK/omni.csv"
limit 30 "$BIN/hcosim" up "$WORK/up.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?"
stop_echoes "${PIDS[0]}" "${PIDS[1]}" "${PIDS[2]}"
summary=$(grep "omni:.*ticks" "$WORK/out/logs/omni.log") || fail "no summary from the haptic service"
answered=$(echo "$summary" | sed -nE 's/.* ([0-9]+) answered.*/\1/p')
[ "${answered:-0}" -gt 1000 ] || fail "only ${answered:-0} states answered by the wall: $summary"
echo "$summary" | grep -qE "round trip p50 [0-9]+ us p99 [0-9]+ us" || fail "no round trip figures: $summary"
# Hand 200 N/m pulling 10 mm behind a 500 N/m wall: the tip rests 2.86 mm in.
zs=$(grep -oE '"position":\{"x":[^}]*"z":-?[0-9.e+-]+' "$WORK/state.log" | sed -E 's/.*"z"://')
[ -n "$zs" ] || fail "no HapticState from the service on the wire"
echo "$zs" | tail -n 500 | awk '{ s += $1; n++ } END { d = -s / n; exit !(d > 0.00255 && d < 0.00315) }' ||
  fail "settled depth not 2.86 mm: $(echo "$zs" | tail -n 3 | tr '\n' ' ')"
fz=$(grep -oE '"rendered_force":\{"x":[^}]*"z":-?[0-9.e+-]+' "$WORK/state.log" | sed -E 's/.*"z"://')
echo "$fz" | awk '{ if ($1 > m) m = $1 } END { exit !(m > 1.2 && m <= 3.3) }' || fail "rendered force out of range"
# One answer in 50 carries a NaN force: refused and counted, never output.
grep '"service":"omni"' "$WORK/status.log" | grep -q '"samples_rejected":[1-9]' || fail "omni did not count NaN forces"
grep -q 'ForceFeedback: force.y is' "$WORK/status.log" || fail "rejection reason missing"
grep -q 'null' "$WORK/state.log" && fail "a non-finite value reached HapticState"
# An overrun tick is skipped, so a loaded machine publishes fewer than the
# 4000 states of 4 s (about 3000 in a parallel ctest run, of which 2766
# were recorded, failing a fixed bound of 3000): the recording must hold
# nine in ten of those the device published.
rows=$(($(wc -l <"$WORK/omni.csv") - 1))
published=$(grep -oE '"seq":[0-9]+' "$WORK/state.log" | sed 's/"seq"://' | sort -n | tail -1)
[ "${published:-0}" -gt 1000 ] || fail "the device published only ${published:-0} states"
[ "$rows" -ge $((published * 9 / 10)) ] || fail "recorded only $rows of about $published samples"
# The replay device plays the recording: each state it publishes holds the
# recording's position at its device time, point by point, and the part
# replayed must reach into the wall. The echo listens until the deployment
# has ended, and the replay lasts 3 s: an echo that started 1.8 s late on a
# loaded CI machine, and a fixed 4 s deadline that can end it before the
# replay does, once left 363 states to compare.
deployment replay.yaml <<'YAML'
mode: realtime
duration: 3
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {device: replay, replay: omni.csv}
YAML
start replayed "$BIN/hcosim" echo HapticState --count 0
limit 30 "$BIN/hcosim" up "$WORK/replay.yaml" --out "$WORK/out2" >"$WORK/up2.log" 2>&1 || fail "replay up exited $?"
stop_echoes "${PIDS[3]}"
sed -nE 's/.*"device_time_s":([0-9.e+-]+),"position":\{"x":[^}]*"z":(-?[0-9.e+-]+).*/\1 \2/p' "$WORK/replayed.log" >"$WORK/replayed.tz"
verdict=$(tail -n +2 "$WORK/omni.csv" | tr , ' ' | awk -v played="$WORK/replayed.tz" '
  { t[n] = $1; z[n] = $4; n++ }
  END {
    while ((getline line < played) > 0) {
      split(line, f, " ")
      while (i + 1 < n && t[i + 1] <= f[1]) i++
      w = (i + 1 < n && f[1] > t[i]) ? (f[1] - t[i]) / (t[i + 1] - t[i]) : 0
      want = z[i] + w * (z[i + 1 < n ? i + 1 : i] - z[i])
      d = f[2] - want; if (d < 0) d = -d
      if (d > worst) { worst = d; at = f[1] }
      if (f[2] < deepest) deepest = f[2]
      m++
    }
    printf "%d states, worst %.3g m at %.3f s, deepest %.5f", m, worst, at, deepest
    exit !(m > 1000 && worst < 1e-4 && deepest < -0.002)
  }') || fail "the replay does not play the recording: $verdict"
echo "haptic_test: ok ($summary; recorded $rows of $published states; replay: $verdict)"

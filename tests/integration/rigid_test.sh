# The rigid body service in a real deployment, in crosscheck mode: the
# virtual user strikes a sphere resting on the marker, then presses a cube
# beside it; a probe sends NaN haptic states, which must be refused and
# counted. States and divergences reach subscribers; the struck sphere
# rolls away, the pressed cube stays and pushes back; the analytic model
# and MuJoCo, given the same loads from the stylus's couplings, stay within
# a centimetre of each other. The run is lockstep, so every run is the same
# one (the sphere rolls 1.0555 m and the models end 0.26 mm apart); in real
# time, or in lockstep before a step waited for its inputs, the strike
# landed differently from run to run. A body placed inside the marker plane
# is refused with its file and line.
source "$(dirname "$0")/lib.sh"
cat >"$WORK/strike.yaml" <<'YAML'
start: [-0.075, 0, 0.02]
actions:
  - hold: {duration: 0.3}
  - move_to: {to: [0.06, 0, 0.02], speed: 0.4}
  - move_to: {to: [0.06, 0, 0.07], speed: 0.1}
  - move_to: {to: [-0.04, 0.04, 0.07], speed: 0.1}
  - move_to: {to: [-0.04, 0.04, 0.043], speed: 0.05}
  - press: {depth: 0.005, speed: 0.01}
  - hold: {duration: 3}
YAML
deployment up.yaml <<'YAML'
mode: lockstep
duration: 6
services:
  - name: omni
    kind: haptic
    rate: 1000
    params: {script: strike.yaml, centre: [0, 0, 0.04]}
  - name: rigid
    kind: rigid
    rate: 1000
    params:
      device: omni
      backend: crosscheck
      bodies:
        - {name: ball, shape: sphere, size: 0.02, mass: 0.1, centre: [0, 0, 0.02]}
        - {name: box, shape: cube, size: 0.02, mass: 0.2, centre: [-0.04, 0.04, 0.02]}
  - name: bad
    kind: test_probe
    rate: 200
    params: {role: source, nan_every: 2}
YAML
start states "$BIN/hcosim" echo RigidBodyState --count 200 --timeout 10
start divergence "$BIN/hcosim" echo RigidDivergence --count 200 --timeout 10
start status "$BIN/hcosim" echo ServiceStatus --count 0 --timeout 10
limit 40 "$BIN/hcosim" up "$WORK/up.yaml" --out "$WORK/out" >"$WORK/up.log" 2>&1 || fail "up exited $?"
wait "${PIDS[0]}" || fail "fewer than 200 body states reached the subscriber"
wait "${PIDS[1]}" || fail "fewer than 200 divergences reached the subscriber"
log="$WORK/out/logs/rigid.log"
grep -q '"body":"ball".*"backend":"analytic"' "$WORK/states.log" || fail "no analytic ball state on the wire"
ball=$(grep "^ball: sphere at" "$log") || fail "no summary for the ball"
echo "$ball" | awk -F'[][, ]+' '{ exit !($4 > 0.1) }' || fail "the struck ball did not roll 10 cm along +x: $ball"
box=$(grep "^box: cube at" "$log") || fail "no summary for the box"
echo "$box" | awk -F'[][, ]+' '{ dx = $4 + 0.04; dy = $5 - 0.04; dz = $6 - 0.02
  exit !(dx * dx + dy * dy + dz * dz < 4e-6) }' || fail "the pressed box moved more than 2 mm: $box"
summary=$(grep "crosscheck backend" "$log") || fail "no service summary"
echo "$summary" | awk '{ for (i = 1; i <= NF; i++) if ($i == "force") f = $(i + 1) } END { exit !(f > 0.2 && f <= 3.3) }' ||
  fail "max force outside 0.2..3.3 N (the clamp): $summary"
div=$(grep "max divergence from MuJoCo" "$log") || fail "no divergence summary"
echo "$div" | awk '{ for (i = 1; i <= NF; i++) if ($i == "position") p = $(i + 1) } END { exit !(p < 0.01) }' ||
  fail "the analytic model and MuJoCo drifted a centimetre apart: $div"
grep -E '"service":"rigid"' "$WORK/status.log" | grep -qE '"samples_rejected":[1-9]' ||
  fail "NaN haptic states were not counted as rejected by rigid"

# A sphere of radius 2 cm centred 1 cm above the marker starts inside it.
sed 's/centre: \[0, 0, 0.02\]}/centre: [0, 0, 0.01]}/' "$WORK/up.yaml" >"$WORK/bad.yaml"
"$BIN/hcosim_rigid" --name rigid --rate 1000 --domain "$DOMAIN" --deployment "$WORK/bad.yaml" \
  >"$WORK/bad.log" 2>&1
code=$?
[ $code -eq 2 ] || fail "a body inside the marker plane exited $code, expected 2"
grep -qE "bad.yaml:[0-9]+:[0-9]+: centre z must be at least size" "$WORK/bad.log" ||
  fail "the error does not name the file, line and problem: $(cat "$WORK/bad.log")"
echo "rigid_test: ok"

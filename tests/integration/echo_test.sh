# hcosim echo, topics and hz against a running service in another process.
source "$(dirname "$0")/lib.sh"
probe src 200 source

out=$(limit 20 "$BIN/hcosim" echo HapticState --count 3 --timeout 15) || fail "echo exited $?: $out"
[ "$(echo "$out" | wc -l)" -eq 3 ] || fail "expected 3 lines, got: $out"
echo "$out" | grep -q '"device":"probe"' || fail "echo lines lack the device: $out"
echo "$out" | head -1 | grep -qE '^\{"device":"probe","seq":[0-9]+,"stamp":\{' || fail "not JSON of HapticState: $out"

# 5 s: discovering a fresh participant takes seconds on a loaded 2-core machine.
topics=$(limit 20 "$BIN/hcosim" topics --wait 5) || fail "topics exited $?"
echo "$topics" | grep -qE '^HapticState +hcosim::HapticState +1 ' || fail "topics misses HapticState: $topics"
echo "$topics" | grep -qE '^ServiceStatus +hcosim::ServiceStatus' || fail "topics misses ServiceStatus: $topics"

hz=$(limit 20 "$BIN/hcosim" hz HapticState --duration 3) || fail "hz exited $?: $hz"
rate=$(echo "$hz" | sed -nE 's/.*: ([0-9.]+) Hz.*/\1/p' | tail -1)
# The probe runs at 200 Hz; a broad band only checks that hz measures a rate.
awk -v r="$rate" 'BEGIN { exit !(r > 100 && r < 300) }' || fail "hz measured '$rate' Hz for a 200 Hz topic: $hz"

err=$("$BIN/hcosim" echo NoSuchTopic 2>&1); code=$?
[ $code -eq 2 ] || fail "unknown topic exited $code"
echo "$err" | grep -q "unknown topic 'NoSuchTopic' (known: HapticState, ForceFeedback" || fail "message: $err"
echo "echo_test: ok"

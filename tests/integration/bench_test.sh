# hcosim bench writes DIR/SUITE.json in the documented shape, with the
# hcosim row compared to bare Fast DDS measured in the same run.
source "$(dirname "$0")/lib.sh"
timeout 100 "$BIN/hcosim" bench dds --quick --domain "$DOMAIN" --out "$WORK/b" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?"
f="$WORK/b/dds.json"
[ -s "$f" ] || fail "no $f"
grep -qE '^\{"suite":"dds","description":"[^"]+","machine":\{"host":' "$f" || fail "header: $(head -c 300 "$f")"
for impl in bare hcosim; do
  grep -qE "\{\"name\":\"rtt\",\"params\":\{\"impl\":\"$impl\",[^}]*\},\"metrics\":\{\"p50_us\":[0-9.e+-]+,\"p99_us\":[0-9.e+-]+," "$f" ||
    fail "no $impl rtt row with numeric p50_us/p99_us: $(cat "$f")"
done
grep -qE '"p99_ratio_to_bare":[0-9.e+-]+' "$f" || fail "no ratio to bare"
grep -qE '"loss_ratio":(0|0\.0[0-9]*|[0-9.e-]+)' "$f" || fail "no loss ratio"
err=$("$BIN/hcosim" bench nosuch --out "$WORK/b" 2>&1); code=$?
[ $code -eq 2 ] && echo "$err" | grep -q "unknown suite 'nosuch' (suites: dds, massspring, haptic, hybrid, rigid, tracking, arview, all)" || fail "unknown suite: $code $err"
echo "bench_test: ok"
cat "$f"

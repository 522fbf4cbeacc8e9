# hcosim bench soak --quick: the default deployment in real time for 30
# s, watched from the bench: three 10 s windows whose rows carry the
# services' memory, overruns (all, and the haptic-rate services'), loss
# on reliable topics and the haptic round trip (answers counted, so the
# loop ran throughout); the summary row is what the windows say
# (recomputed here); index.md judges the four goals from it and shows
# both plots; no process is left behind.
# The goals' verdicts are reported, not asserted.
source "$(dirname "$0")/lib.sh"
limit 180 "$BIN/hcosim" bench soak --quick --domain "$DOMAIN" --out "$WORK/b" --work "$WORK/w" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?: $(tail -5 "$WORK/bench.log")"
f="$WORK/b/soak.json"
[ -s "$f" ] || fail "no $f"
problems=$(jq -r '
  [.rows[] | select(.name == "window")] as $w
  | [.rows[] | select(.name == "summary")][0].metrics as $s
  | (if ($w | length) != 3 then "\($w | length) windows, not 3" else empty end),
    ($w[] | . as $r | ("rss_mb", "haptic_rtt_p50_us", "haptic_rtt_p99_us", "answers")
       | select(($r.metrics[.] | type) != "number" or $r.metrics[.] <= 0) | "window \($r.params.t_s): \(.) missing or not positive"),
    ($w[] | select(.metrics.reliable_lost < 0 or .metrics.overruns < 0 or .metrics.haptic_overruns < 0
                   or .metrics.haptic_overruns > .metrics.overruns) | "window \(.params.t_s): counts out of range"),
    (if $s == null then "no summary row" else empty end),
    (($w[-1].metrics.rss_mb / $w[0].metrics.rss_mb - 1) * 100 | select(. - $s.rss_growth_pct | fabs > 1e-6)
       | "rss_growth_pct \($s.rss_growth_pct), the windows say \(.)"),
    ((($w[-1].metrics.haptic_rtt_p99_us - $w[0].metrics.haptic_rtt_p99_us) / $w[0].metrics.haptic_rtt_p99_us * 100 | fabs)
       | select(. - $s.p99_drift_pct | fabs > 1e-6) | "p99_drift_pct \($s.p99_drift_pct), the windows say \(.)"),
    ([$w[].metrics.reliable_lost] | add | select(. != $s.reliable_lost) | "reliable_lost \($s.reliable_lost), windows \(.)"),
    ([$w[].metrics.haptic_overruns] | add | select(. != $s.haptic_overruns)
       | "haptic_overruns \($s.haptic_overruns), windows \(.)")
  ' "$f") || fail "jq could not read $f"
[ -z "$problems" ] || fail "soak rows: $problems"
for goal in "memory grows under 1%" "no sample lost on reliable topics" "haptic round-trip p99 within 20%" \
  "no overrun on the haptic-rate services"; do
  grep -qE "$goal.*\*\*(met|not met)" "$WORK/b/index.md" || fail "index.md does not judge '$goal': $(grep -i goal -A6 "$WORK/b/index.md")"
done
for png in soak_window_haptic_rtt_p99_us.png soak_window_rss_mb.png; do
  [ -s "$WORK/b/$png" ] || fail "no plot $png"
done
for pid in $(sed -nE 's/.*started +[a-z]+ +pid ([0-9]+).*/\1/p' "$WORK/w/soak_run/up.log"); do
  alive "$pid" && fail "process $pid of the soak still running"
done
echo "bench_soak_test: ok ($(jq -c '[.rows[] | select(.name == "summary")][0].metrics' "$f"))"

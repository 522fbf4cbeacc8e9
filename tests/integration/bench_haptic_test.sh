# hcosim bench haptic --quick: the closed loop through hcosim_haptic and a
# force peer in another process, the bare Fast DDS baseline from the same
# run, the default scene in real time through hcosim up with a bare pair
# beside it (on the next domain, reserved for it in tests/CMakeLists.txt),
# and a wall row per delay and stiffness, every one stable.
source "$(dirname "$0")/lib.sh"
limit 200 "$BIN/hcosim" bench haptic --quick --domain "$DOMAIN" --out "$WORK/b" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?: $(tail -5 "$WORK/bench.log")"
f="$WORK/b/haptic.json"
[ -s "$f" ] || fail "no $f"
num='[0-9][0-9.e+-]*'
grep -qE "\"name\":\"closed_loop_rtt\",[^}]*\},\"metrics\":\{\"p50_us\":$num,\"p99_us\":$num,\"on_time_ratio\":$num,\"ticks\":$num,\"p99_ratio_to_bare\":$num" "$f" ||
  fail "no closed_loop_rtt row with its metrics"
grep -qE "\"name\":\"bare_fastdds_rtt\",[^}]*\},\"metrics\":\{\"p50_us\":$num,\"p99_us\":$num" "$f" || fail "no bare_fastdds_rtt row"
# A loop that works answers most ticks within the tick; one that is broken
# (answers late or never) almost none. The margin is for a shared 2-core
# machine running other tests beside it (0.898 seen in a full ctest -j2).
ratio=$(grep -oE "\"on_time_ratio\":$num" "$f" | cut -d: -f2)
awk -v r="$ratio" 'BEGIN { exit !(r > 0.5) }' || fail "only $ratio of ticks answered in time"
# The default scene's row: every metric, from a run as long as asked, its
# goals judged in the report. How well it holds real time on this shared
# machine is reported there, not asserted here.
grep -qE "\"name\":\"deployment\",\"params\":\{\"seconds\":20(\.0)?\},\"metrics\":\{\"jitter_p50_us\":$num,\"jitter_p99_us\":$num,\"bare_jitter_p50_us\":$num,\"bare_jitter_p99_us\":$num,\"in_tick_ratio\":$num,\"rtt_p50_us\":$num,\"rtt_p99_us\":$num,\"bare_p50_us\":$num,\"bare_p99_us\":$num,\"bare_within_0_8ms_ratio\":$num,\"p99_ratio_to_bare\":$num,\"force_error_p99_n\":$num,\"peak_force_n\":$num,\"force_error_share\":$num,\"covered_source_ticks\":$num,\"ticks\":$num\}" "$f" ||
  fail "no deployment row with its metrics: $(grep -oE '\{"name":"deployment"[^}]*\}[^}]*\}' "$f")"
ticks=$(jq '.rows[] | select(.name == "deployment") | .metrics.ticks' "$f")
# Ticks skipped by overruns are not counted: a margin for them.
awk -v t="$ticks" 'BEGIN { exit !(t >= 15000) }' || fail "the deployment ran $ticks ticks, not about 20 s of them"
grep -qF -- '- Goal: at least 99.9% of the default scene'"'"'s ticks answered by every source within the tick (`in_tick_ratio` at least 0.999 in every `deployment` row): **' "$WORK/b/index.md" ||
  fail "the report does not judge the in-tick goal: $(grep Goal "$WORK/b/index.md")"
walls=$(grep -oE "\"name\":\"wall\",\"params\":\{\"delay_ms\":$num,\"stiffness_n_per_m\":$num\},\"metrics\":\{\"max_force_n\":$num,\"energy_out_j\":$num,\"stable\":[01]" "$f" | wc -l)
[ "$walls" -eq 15 ] || fail "expected 15 wall rows, found $walls"
grep -qE '"stable":0' "$f" && fail "an unstable wall: $(grep -oE '\{"name":"wall"[^}]*\},"metrics":\{[^}]*"stable":0[^}]*\}' "$f")"
echo "bench_haptic_test: ok (on time $ratio)"

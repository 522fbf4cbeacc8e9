# hcosim bench foxglove --quick: the default scene in real time without
# and with the bridge and a client subscribed to everything: each run's
# round trip and in-tick share, the bridge's CPU share from /proc (alone,
# receiving every topic, and then serving the client: more), what the
# client received (every channel subscribed, the meshes' scene channels
# and the camera's images arriving), and both goals judged in the report.
# How close to its goals it comes on this shared machine is reported
# there, not asserted here.
source "$(dirname "$0")/lib.sh"
limit 200 "$BIN/hcosim" bench foxglove --quick --domain "$DOMAIN" --out "$WORK/b" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?: $(tail -5 "$WORK/bench.log")"
f="$WORK/b/foxglove.json"
[ -s "$f" ] || fail "no $f"
on=$(jq -c '.rows[] | select(.name == "run" and .params.bridge == "on") | .metrics' "$f")
off=$(jq -c '.rows[] | select(.name == "run" and .params.bridge == "off") | .metrics' "$f")
[ -n "$on" ] && [ -n "$off" ] || fail "no run rows with and without the bridge: $(cat "$f")"
echo "$off" | jq -e '.rtt_p99_us > 0 and .in_tick_ratio > 0' >/dev/null || fail "the run without: $off"
# The client subscribed to all 20 channels of the default scene (11 topics,
# 6 objects and the stylus, tf, the camera), and the scene came: a broken
# bridge sends nothing or only the topics.
echo "$on" | jq -e '.channels == 20 and .statuses == 0 and .cpu_share_no_client > 0 and
  .cpu_share > .cpu_share_no_client and .client_mb_per_s > 1' >/dev/null ||
  fail "the run with the bridge: $on"
echo "$on" | jq -e '.cube_scene_per_s > 5 and .organ_scene_per_s > 5 and .images_per_s > 5' >/dev/null ||
  fail "scene updates or images missing: $on"
jq -e '.rows[] | select(.name == "bridge") | .metrics | (.cpu_share > 0) and (.cpu_share_no_client > 0) and
  (.p99_change | type == "number")' "$f" \
  >/dev/null || fail "no bridge row: $(cat "$f")"
for goal in "cpu_share\` at most 0.1" "p99_change\` at most 0.1"; do
  grep -qF -- "$goal in every \`bridge\` row): **" "$WORK/b/index.md" ||
    fail "the report does not judge $goal: $(grep Goal "$WORK/b/index.md")"
done
echo "bench_foxglove_test: ok: $(jq -c '.rows[] | select(.name == "bridge") | .metrics' "$f")"

# hcosim bench dds --quick: DIR/dds.json in the documented shape, hcosim's
# rows compared to bare Fast DDS measured in the same run, hcosim's meshes
# of up to 10^4 vertices delivered without loss, and DIR/index.md
# reporting them with its goals judged from the same rows, plots and the
# machine; `bench report` draws the same report again from the JSON file.
# What this shared machine can carry is reported, not asserted: every
# latency, bare Fast DDS's losses, and losses at 10^5 vertices (2.4 MB
# samples at 60 Hz to 3 readers: with KEEP_LAST 16 a reader more than
# 266 ms behind loses the oldest, docs/topics.md), which both impls may
# show on a loaded machine. Counted samples follow a warm-up (startup_ms):
# a reader's first moments, while the processes start, lose the most.
# Between hosts made of network
# namespaces (where this machine can make them), 10^5-vertex meshes to a
# reader on each of two other hosts over UDP must arrive, none lost.
source "$(dirname "$0")/lib.sh"
limit 300 "$BIN/hcosim" bench dds --quick --domain "$DOMAIN" --out "$WORK/b" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?: $(tail -5 "$WORK/bench.log")"
grep -q "bench: \[1/1\] dds: " "$WORK/bench.log" || fail "no progress line: $(head -3 "$WORK/bench.log")"
f="$WORK/b/dds.json"
[ -s "$f" ] || fail "no $f"
grep -qE '^\{"suite":"dds","description":"[^"]+","machine":\{"date":"[^"]+","host":' "$f" || fail "header: $(head -c 300 "$f")"
problems=$(jq -r '
  .rows as $rows
  | def rtt($i): [$rows[] | select(.name == "rtt" and .params.impl == $i)][0].metrics;
    def mesh($v; $s; $i): [$rows[] | select(.name == "mesh_pub" and .params.vertices == $v
                                             and .params.subscribers == $s and .params.impl == $i)][0].metrics;
  ([("bare", "hcosim") as $i | ("p50_us", "p99_us", "loss_ratio") as $k
    | select((rtt($i)[$k] | type) != "number") | "rtt \($i): no \($k)"]
   + [if (rtt("hcosim").p99_ratio_to_bare | type) != "number" then "rtt: no ratio to bare" else empty end]
   + [(1000, 10000, 100000) as $v | (1, 3) as $s | ("bare", "hcosim") as $i | mesh($v; $s; $i) as $m
      | if $m == null then "mesh_pub \($v) \($s) \($i): no row"
        elif ([$m.p50_ms, $m.p99_ms, $m.cpu_pct] | map(type == "number" and . > 0) | all) | not
          then "mesh_pub \($v) \($s) \($i): p50_ms, p99_ms or cpu_pct missing or not positive"
        elif $m.p50_ms > $m.p99_ms then "mesh_pub \($v) \($s) \($i): p50 \($m.p50_ms) above p99 \($m.p99_ms) ms"
        elif ($m.loss_ratio | type) != "number" then "mesh_pub \($v) \($s) \($i): no loss_ratio"
        elif $i == "hcosim" and $v <= 10000 and $m.loss_ratio != 0
          then "mesh_pub \($v) \($s): hcosim lost \($m.loss_ratio) of the samples (RELIABLE)"
        elif $m.samples != 120 * $s then "mesh_pub \($v) \($s) \($i): \($m.samples) samples, not \(120 * $s)"
        elif $i == "hcosim" and ($m.p99_ratio_to_bare | type) != "number" then "mesh_pub \($v) \($s): no ratio to bare"
        else empty end])
  | .[]' "$f") || fail "jq could not read $f"
[ -z "$problems" ] || fail "dds rows: $problems; $(grep -F missed "$WORK/bench.log" | head -6)"

# Between hosts made of network namespaces, where this machine can make
# them: round trips between two, 10^5-vertex meshes from one to a reader
# on each of two others and a camera's frames from one to another, over
# UDP, reliable, none lost.
if skipped=$(grep -o "dds between hosts: skipped: .*" "$WORK/bench.log"); then
  echo "bench_test: $skipped"
else
  problems=$(jq -r '
    .rows as $rows
    | def row($n; $i): [$rows[] | select(.name == $n and .params.impl == $i)][0].metrics;
    def large($n; $samples; $what): [("bare", "hcosim") as $i | row($n; $i) as $m
        | if $m == null then "\($n) \($i): no row"
          elif ([$m.p50_ms, $m.p99_ms, $m.cpu_pct] | map(type == "number" and . > 0) | all) | not
            then "\($n) \($i): p50_ms, p99_ms or cpu_pct missing or not positive"
          elif $m.samples != $samples then "\($n) \($i): \($m.samples) samples, not \($samples)"
          elif $i == "hcosim" and $m.loss_ratio != 0
            then "\($n): hcosim lost \($m.loss_ratio) of \($what) between hosts (RELIABLE)"
          else empty end];
    ([("bare", "hcosim") as $i | ("p50_us", "p99_us") as $k
      | select((row("rtt_hosts"; $i)[$k] | type) != "number") | "rtt_hosts \($i): no \($k)"]
     + [if (row("rtt_hosts"; "hcosim").p99_ratio_to_bare | type) != "number" then "rtt_hosts: no ratio to bare" else empty end]
     + large("mesh_hosts"; 240; "the 10^5-vertex meshes") + large("frame_hosts"; 120; "the camera frames"))
    | .[]' "$f") || fail "jq could not read $f"
  [ -z "$problems" ] || fail "dds rows between hosts: $problems; $(grep -F missed "$WORK/bench.log" | head -6)"
  for t in mesh_hosts frame_hosts; do grep -q "^### $t$" "$WORK/b/index.md" || fail "no $t table"; done
  echo "bench_test: between hosts: $(jq -r '[.rows[] | select(.name == "mesh_hosts" and .params.impl == "hcosim")][0].metrics
    | "10^5-vertex meshes to two hosts, none lost, p99 \(.p99_ms) ms"' "$f"); $(jq -r '[.rows[] | select(.name ==
    "frame_hosts" and .params.impl == "hcosim")][0].metrics | "camera frames to another, none lost, p99 \(.p99_ms) ms"' "$f")"
fi

# The report: its p99 goal's verdict follows from the rows.
md="$WORK/b/index.md"
[ -s "$md" ] || fail "no $md"
grep -qE "^Measured by \`hcosim bench dds --quick --domain $DOMAIN --out $WORK/b\` at commit \`[0-9a-f]{40}\` \((a clean tree|\*\*with changes git had not committed\*\*)\)\. " "$md" ||
  fail "index.md does not name its command: $(sed -n 3p "$md")"
grep -q '^### mesh_pub$' "$md" || fail "no mesh_pub table"
[ "$(grep -cE '^\| (1000|10000|100000) \| (1|3) \| (bare|hcosim) \| 60 \|' "$md")" -eq 12 ] ||
  fail "expected 12 mesh_pub table rows: $(grep -A16 '^### mesh_pub' "$md")"
lost=$(jq '[.rows[] | select(.name == "mesh_pub" and .params.impl == "hcosim") | .metrics.loss_ratio] | max' "$f")
verdict=$(awk -v l="$lost" 'BEGIN { print (l <= 0 ? "**met**" : "**not met**") }')
grep -qF -- "- Goal: no sample lost with reliable QoS (\`loss_ratio\` at most 0 in every \`mesh_pub\` row with impl hcosim): $verdict" "$md" ||
  fail "loss goal should be $verdict (worst loss $lost): $(grep 'Goal' "$md")"
worst=$(jq '[.rows[] | select(.name == "mesh_pub" and .params.impl == "hcosim") | .metrics.p99_ratio_to_bare] | max' "$f")
verdict=$(awk -v w="$worst" 'BEGIN { print (w <= 1.2 ? "**met**" : "**not met**") }')
grep -qF "times bare Fast DDS's (\`p99_ratio_to_bare\` at most 1.2 in every \`mesh_pub\` row with impl hcosim): $verdict" "$md" ||
  fail "p99 goal should be $verdict (worst ratio $worst): $(grep 'Goal' "$md")"
for png in dds_mesh_pub_p99_ms.png dds_mesh_pub_cpu_pct.png; do
  grep -qF "]($png)" "$md" || fail "index.md does not show $png"
  [ "$(head -c 8 "$WORK/b/$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$png is not a PNG"
done
grep -q '^| fastdds | 2\.9\.1 |$' "$md" || fail "no machine section: $(tail -12 "$md")"

# `bench report` draws the same report again from dds.json alone.
mv "$md" "$WORK/first.md"
rm "$WORK"/b/*.png
"$BIN/hcosim" bench report --out "$WORK/b" >"$WORK/report.log" 2>&1 || fail "bench report exited $?: $(cat "$WORK/report.log")"
grep -qF "(this report drawn again from its JSON files by \`hcosim bench report --out $WORK/b\`)" "$md" ||
  fail "the redrawn report does not say so: $(sed -n 3p "$md")"
diff <(sed 1,4d "$WORK/first.md") <(sed 1,4d "$md") >"$WORK/report.diff" || fail "the redrawn report differs: $(head "$WORK/report.diff")"
[ -s "$WORK/b/dds_mesh_pub_p99_ms.png" ] || fail "bench report drew no plot"

err=$("$BIN/hcosim" bench nosuch --out "$WORK/b" 2>&1); code=$?
[ $code -eq 2 ] && echo "$err" | grep -q "unknown suite 'nosuch' (suites: dds, massspring, haptic, hybrid, rigid, contact, tracking, arview, foxglove, soak, all)" || fail "unknown suite: $code $err"
echo "bench_test: ok (worst hcosim/bare p99 ratio $worst)"

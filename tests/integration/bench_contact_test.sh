# hcosim bench contact: every kind's row carries the metrics its scene
# measures, and its goals hold for every kind: the
# stroke's tangential over normal force at most the friction + 0.02 and in
# contact throughout, entering between nodes within 5 degrees of the
# normal, no onset above stiffness x motion, a hold's spread under 2 %,
# and the pushed cube's force within 20 % of friction x weight.
source "$(dirname "$0")/lib.sh"
limit 400 "$BIN/hcosim" bench contact --domain "$DOMAIN" --out "$WORK/b" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?: $(tail -5 "$WORK/bench.log")"
f="$WORK/b/contact.json"
[ -s "$f" ] || fail "no $f"
problems=$(jq -r '
  .rows as $rows
  | def m($k): [$rows[] | select(.params.kind == $k)][0].metrics;
  ([("hybrid_cube", "sheet", "semisphere", "rigid_cube") as $k
    | ("onset_ratio", "hold_spread_pct", "stroke_ratio_max", "entry_angle_deg") as $x
    | select((m($k)[$x] | type) != "number") | "\($k): \($x) missing"]
   + [("organ_stiff_side", "rigid_sphere") as $k | ("onset_ratio", "hold_spread_pct") as $x
      | select((m($k)[$x] | type) != "number") | "\($k): \($x) missing"]
   + [("hybrid_cube", "sheet", "semisphere", "rigid_cube") as $k | m($k) as $o
      | (if $o.stroke_excess > 0.02 then "\($k): stroke ratio \($o.stroke_ratio_max) over mu \($o.friction) + 0.02"
         else empty end),
        (if $o.stroke_in_contact_pct < 99 then "\($k): in contact \($o.stroke_in_contact_pct) % of the stroke"
         else empty end),
        (if $o.entry_angle_deg > 5 then "\($k): entry \($o.entry_angle_deg) degrees off the normal" else empty end)]
   + [$rows[] | .params.kind as $k | .metrics as $o
      | (if $o.onset_ratio > 1 then "\($k): onset \($o.onset_ratio) x stiffness x motion" else empty end),
        (if $o.hold_spread_pct > 2 then "\($k): hold spread \($o.hold_spread_pct) %" else empty end)]
   + (m("rigid_cube") as $o
      | [if ($o.push_ratio | type) != "number" or $o.push_ratio > 1.2 or $o.push_ratio < 0.8
         then "pushed cube: \($o.push_ratio) of friction x weight" else empty end]))
  | .[]' "$f") || fail "jq could not read $f"
[ -z "$problems" ] || fail "contact rows: $problems"
echo "bench_contact_test: ok"

# hcosim bench arview --quick: the AR view's frame rows carry their
# metrics, the 10800-triangle mesh and the default scene at 640x480 count
# their triangles, and the OpenCV baseline drew the same picture (under 2%
# of the pixels apart), so the speed ratio compares the same work. Speed
# is reported, not asserted.
source "$(dirname "$0")/lib.sh"
limit 100 "$BIN/hcosim" bench arview --quick --out "$WORK/b" --work "$WORK/w" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?: $(tail -5 "$WORK/bench.log")"
f="$WORK/b/arview.json"
[ -s "$f" ] || fail "no $f"
problems=$(jq -r '
  .rows as $rows
  | def m($s): [$rows[] | select(.name == "frame" and .params.scene == $s and .params.resolution == "640x480")][0].metrics;
  ([("one_mesh", "default") as $s
    | ("draw_ms_p50", "draw_ms_p99", "encode_ms_p50", "frame_ms_p50", "fps_p50", "opencv_ms_p50", "ratio_to_opencv") as $k
    | select((m($s)[$k] | type) != "number" or m($s)[$k] <= 0) | "\($s): \($k) missing or not positive"]
   + [if m("one_mesh").triangles != 10800 then "one_mesh has \(m("one_mesh").triangles) triangles" else empty end,
      if m("default").triangles < 20000 then "default has \(m("default").triangles) triangles" else empty end,
      (("one_mesh", "default") as $s | if m($s).differ_pct > 2 then "\($s): the pictures differ on \(m($s).differ_pct)%"
                                         else empty end)])
  | .[]' "$f") || fail "jq could not read $f"
[ -z "$problems" ] || fail "arview rows: $problems"
[ ! -e "$WORK/w/arview_bench.mp4" ] || fail "the bench left its scratch video behind"
echo "bench_arview_test: ok"

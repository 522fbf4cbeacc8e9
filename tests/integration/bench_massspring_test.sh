# hcosim bench massspring --quick: a row per integrator with time and
# error, adaptive rows, MuJoCo on the same lattice with the speed-up at
# equal error, one Pareto PNG per lattice, and the elastic surfaces'
# recovery rows.
source "$(dirname "$0")/lib.sh"
limit 240 "$BIN/hcosim" bench massspring --quick --out "$WORK/b" >"$WORK/bench.log" 2>&1 ||
  fail "bench exited $?: $(tail -5 "$WORK/bench.log")"
f="$WORK/b/massspring.json"
[ -s "$f" ] || fail "no $f"
num='-?[0-9][0-9.e+-]*'
for lattice in box216 dome129; do
  for integrator in symplectic_euler velocity_verlet rk4 implicit_euler local_global mujoco; do
    grep -qE "\"params\":\{\"lattice\":\"$lattice\",[^}]*\"integrator\":\"$integrator\",[^}]*\},\"metrics\":\{\"ms_per_sim_s\":$num,\"rel_error\":$num," "$f" ||
      fail "no $lattice $integrator row with numeric ms_per_sim_s and rel_error"
  done
  for variant in Euler RK4; do
    grep -qE "\"lattice\":\"$lattice\",[^}]*\"integrator\":\"mujoco\",[^}]*\"mujoco_integrator\":\"$variant\"" "$f" ||
      fail "no $lattice row for MuJoCo's $variant"
  done
  grep -qE "\"lattice\":\"$lattice\",[^}]*\"threshold\":1e-08\}" "$f" || fail "no adaptive row for $lattice"
  grep -qE "\"lattice\":\"$lattice\",[^}]*\"mujoco_integrator\":\"Euler\",\"matched_by\":\"[^\"]+\"\},\"metrics\":\{[^}]*\"speedup_at_equal_error\":$num" "$f" ||
    fail "no speed-up at equal error for $lattice"
  grep -qE "\{\"name\":\"reference\",\"params\":\{\"lattice\":\"$lattice\"[^}]*\},\"metrics\":\{\"ref_self_error\":$num" "$f" ||
    fail "no reference row for $lattice"
  png="$WORK/b/massspring_step_$lattice.png"
  [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "$png is not a PNG"
done
# The elastic surfaces with their hinges come back within 0.1 mm of rest 2 s
# after release; as membranes the dome stays dented.
for shape in semisphere sheet; do
  grep -qE "\"name\":\"recovery\",\"params\":\{\"shape\":\"$shape\",\"model\":\"hinges\",[^}]*\},\"metrics\":\{\"off_1s_mm\":$num,\"off_2s_mm\":(0\.0[0-9]*|[0-9.]*e-[0-9]+)," "$f" ||
    fail "no $shape recovery row within 0.1 mm: $(grep -oE "\"shape\":\"$shape\",\"model\":\"hinges\"[^]]{0,300}" "$f" | head -c 400)"
done
grep -qE "\"shape\":\"semisphere\",\"model\":\"membrane\",[^}]*\},\"metrics\":\{\"off_1s_mm\":$num,\"off_2s_mm\":[1-9][0-9.]*," "$f" ||
  fail "the dome without hinges recovered: the recovery rows cannot tell"
# against_fem: the modal reduction's rows beside the springs', the FEM's
# and Bullet's, every Bullet row with its speed-up at equal error.
for modes in 8 32 300; do
  grep -qE "\"name\":\"against_fem\",\"params\":\{\"model\":\"modal\",[^}]*\"modes\":$modes\.0,[^}]*\},\"metrics\":\{\"rel_error\":$num,\"ms_per_sim_s\":$num" "$f" ||
    fail "no against_fem row for the $modes lowest modes"
done
[ "$(grep -oE "\"model\":\"bullet\",[^}]*\},\"metrics\":\{[^}]*\"speedup_at_equal_error\":$num" "$f" | wc -l)" -eq 9 ] ||
  fail "not every Bullet row has its speed-up at equal error"
# 32 modes of the FEM are closer to the continuum than any springs row.
jq -e '[.rows[] | select(.name == "against_fem")] as $r
  | ([$r[] | select(.params.model == "modal" and .params.modes == 32) | .metrics.rel_error] | max)
    < ([$r[] | select(.params.model == "springs") | .metrics.rel_error] | min)' "$f" >/dev/null ||
  fail "the 32-mode rows are no closer to the FEM reference than the springs"
# The reference has converged far below the errors it judges.
grep -oE "\"ref_self_error\":$num" "$f" | cut -d: -f2 | awk '$1 > 1e-4 { bad = 1 } END { exit bad }' ||
  fail "reference not converged: $(grep -oE "\"ref_self_error\":$num" "$f")"
echo "bench_massspring_test: ok"

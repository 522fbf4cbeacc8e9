# hcosim bench massspring --quick: a row per integrator with time and
# error, adaptive rows, MuJoCo on the same lattice with the speed-up at
# equal error, and one Pareto PNG per lattice.
source "$(dirname "$0")/lib.sh"
limit 100 "$BIN/hcosim" bench massspring --quick --out "$WORK/b" >"$WORK/bench.log" 2>&1 ||
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
# The reference has converged far below the errors it judges.
grep -oE "\"ref_self_error\":$num" "$f" | cut -d: -f2 | awk '$1 > 1e-4 { bad = 1 } END { exit bad }' ||
  fail "reference not converged: $(grep -oE "\"ref_self_error\":$num" "$f")"
echo "bench_massspring_test: ok"

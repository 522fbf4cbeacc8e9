// bench rigid: the rigid model of seed 000 §2.1 against its closed forms
// and against MuJoCo.
//
// eq2: the seed's linear-momentum case (000 eq 2), equal masses and radii,
//   e = 1, no friction, over 201 impact parameters b in [0, 2r]: the
//   largest difference of either outgoing velocity from eq 2's, m/s, for
//   an incoming 1 m/s.
// crosscheck: each scenario of models/rigid/crosscheck.h in both models at
//   `dt_ms` 0.1 (the cross-check's step, where the tolerances hold) and 1
//   (the service's physics rate, to show why not): end velocities' difference over the tip's speed, angular
//   velocities' over tip speed / body size, the scenario's tolerance, and
//   each model's momentum, angular momentum and energy change.
// step: one step of a scene of `bodies` bodies resting on the marker plane
//   with the tip sweeping across them, per backend; MuJoCo is the baseline
//   (ratio in the same run). Analytic bodies that sleep cost nothing, so
//   the analytic rows are also run with sleep disabled.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "models/rigid/crosscheck.h"
#include "services/bench/bench.h"

namespace hcosim::services::bench {
namespace {

using namespace hcosim::models::rigid;
using Clock = std::chrono::steady_clock;

// 000 eq 2's case in one backend at step dt: equal masses and radii, e = 1,
// no friction, over `n` impact parameters b in [0, 2r]; the largest
// difference of either outgoing velocity from eq 2's, m/s for an incoming
// 1 m/s, and the wall time per simulated second.
struct Eq2 {
  double max_abs_err = 0, ms_per_sim_s = 0;
};

Eq2 eq2(bool mujoco, double dt, int n) {
  const double r = 0.02, v1 = 1, duration = 0.2;
  WorldSpec spec;
  spec.gravity.setZero(), spec.ground = false, spec.drag = Drag{0, 0, 0, 0};
  spec.tip = Material{1, 0}, spec.tip_radius = r, spec.tip_mass = 0.1;
  Eq2 out;
  double wall_s = 0;
  for (int k = 0; k <= n - 1; ++k) {
    const double b = 2 * r * k / (n - 1), s = b / (2 * r), c = std::sqrt(1 - s * s);
    Body ball;
    ball.size = r, ball.mass = 0.1;
    const Tip tip{Eigen::Vector3d(-0.1, b, 0), Eigen::Vector3d(v1, 0, 0)};
    const int steps = int(std::lround(duration / dt));
    Eigen::Vector3d ball_end, tip_end;
    // Stepping only: building MuJoCo's model is not part of a step's cost.
    if (mujoco) {
      MujocoWorld w(spec, {ball}, dt);
      w.set_tip(tip);
      const auto t0 = Clock::now();
      for (int i = 0; i < steps; ++i) w.step();
      wall_s += std::chrono::duration<double>(Clock::now() - t0).count();
      ball_end = w.body(0).v, tip_end = w.tip().v;
    } else {
      World w(spec, {ball});
      w.set_tip(tip);
      const auto t0 = Clock::now();
      for (int i = 0; i < steps; ++i) w.step(dt);
      wall_s += std::chrono::duration<double>(Clock::now() - t0).count();
      ball_end = w.bodies()[0].v, tip_end = w.tip().v;
    }
    // eq 2: the ball leaves at sqrt(1 - (b/2r)^2) v1, theta2 = asin(b/2r)
    // off the line (away from the tip), the tip at (b/2r) v1, theta1 =
    // asin(sqrt(1 - (b/2r)^2)) to the other side.
    const Eigen::Vector3d ball_v = c * v1 * Eigen::Vector3d(c, -s, 0), tip_v = s * v1 * Eigen::Vector3d(s, c, 0);
    out.max_abs_err =
        std::max({out.max_abs_err, (ball_end - ball_v).cwiseAbs().maxCoeff(), (tip_end - tip_v).cwiseAbs().maxCoeff()});
  }
  out.ms_per_sim_s = 1e3 * wall_s / (n * duration);
  return out;
}

Row eq2_row() { return {"eq2", {{"impact_parameters", 201.0}}, {{"max_abs_err", eq2(false, 1e-3, 201).max_abs_err}}}; }

// eq 2's case per backend and step: time against error.
std::vector<Row> accuracy_rows(bool quick) {
  std::vector<Row> rows;
  const int n = quick ? 11 : 41;
  for (const bool mujoco : {false, true})
    for (const double dt_ms : {2.0, 1.0, 0.5, 0.2, 0.1}) {
      const Eq2 e = eq2(mujoco, dt_ms * 1e-3, n);
      rows.push_back({"accuracy",
                      {{"backend", std::string(mujoco ? "mujoco" : "analytic")},
                       {"dt_ms", dt_ms},
                       {"impact_parameters", double(n)}},
                      {{"ms_per_sim_s", e.ms_per_sim_s}, {"max_abs_err", e.max_abs_err}}});
    }
  return rows;
}

std::vector<Row> crosscheck_rows() {
  std::vector<Row> rows;
  for (const double dt : {kCrosscheckDt, 1e-3})
    for (const Scenario& s : scenarios()) {
      const Divergence d = crosscheck(s, dt);
      rows.push_back({"crosscheck",
                      {{"scenario", s.name}, {"dt_ms", dt * 1e3}},
                      {{"rel_vel_err", d.rel_vel_err},
                       {"rel_angvel_err", d.rel_angvel_err},
                       {"tolerance", s.tolerance},
                       {"position_err_m", d.position_m},
                       {"analytic_momentum_drift", d.momentum_drift[0]},
                       {"mujoco_momentum_drift", d.momentum_drift[1]},
                       {"analytic_angmom_drift", d.angular_momentum_drift[0]},
                       {"mujoco_angmom_drift", d.angular_momentum_drift[1]},
                       {"analytic_energy_change", d.energy_change[0]},
                       {"mujoco_energy_change", d.energy_change[1]}}});
    }
  return rows;
}

// `n` cubes and spheres in a row on the plane; the tip sweeps along it.
std::vector<Body> row_of(int n) {
  std::vector<Body> out;
  for (int i = 0; i < n; ++i) {
    Body b;
    b.shape = i % 2 ? models::rigid::Shape::cube : models::rigid::Shape::sphere;
    b.size = 0.01, b.mass = 0.05;
    b.x = Eigen::Vector3d(0.05 * i, 0.3 * (i % 3), 0.01);
    out.push_back(b);
  }
  return out;
}

Tip sweep(int k) { return {Eigen::Vector3d(-0.05 + 1e-4 * k, 0, 0.012), Eigen::Vector3d(0.1, 0, 0)}; }

std::vector<Row> step_rows(bool quick) {
  std::vector<Row> rows;
  const int steps = quick ? 300 : 1000;
  for (const int n : quick ? std::vector<int>{1, 10} : std::vector<int>{1, 10, 100}) {
    progress("rigid step: " + std::to_string(n) + " bodies");
    WorldSpec spec;
    std::vector<double> mj;
    {
      MujocoWorld m(spec, row_of(n), 1e-3);
      for (int k = 0; k < steps; ++k) {
        m.set_tip(sweep(k));
        const auto t0 = Clock::now();
        m.step();
        mj.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
      }
    }
    const double base = median(mj);
    rows.push_back({"step",
                    {{"backend", std::string("mujoco")}, {"bodies", double(n)}},
                    {{"us_per_step", base}, {"ratio_to_mujoco", 1.0}}});
    for (const bool sleep : {true, false}) {
      WorldSpec s = spec;
      if (!sleep) s.sleep_time = 1e9;
      World w(s, row_of(n));
      std::vector<double> t;
      for (int k = 0; k < steps; ++k) {
        w.set_tip(sweep(k));
        const auto t0 = Clock::now();
        w.step(1e-3);
        t.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
      }
      const double us = median(t);
      rows.push_back({"step",
                      {{"backend", std::string(sleep ? "analytic" : "analytic_awake")}, {"bodies", double(n)}},
                      {{"us_per_step", us}, {"ratio_to_mujoco", us / base}}});
    }
  }
  return rows;
}

std::vector<Row> rigid_rows(const Context& c) {
  std::vector<Row> rows;
  progress("rigid eq2 over 201 impact parameters");
  rows.push_back(eq2_row());
  progress("rigid eq2 per backend and step, time against error");
  for (Row& r : accuracy_rows(c.quick)) rows.push_back(std::move(r));
  progress("rigid crosscheck against MuJoCo");
  for (Row& r : crosscheck_rows()) rows.push_back(std::move(r));
  for (Row& r : step_rows(c.quick)) rows.push_back(std::move(r));
  return rows;
}

}  // namespace

Suite rigid_suite() {
  Suite s{"rigid",
          "rigid bodies (seed 000): eq 2 against its closed form, scenarios against MuJoCo, step cost per backend",
          rigid_rows};
  s.tables = {
      {"eq2",
       "000 eq 2's case (equal masses and radii, e = 1, no friction, an incoming 1 m/s) in the analytic model at 1 ms "
       "over 201 impact parameters: the largest difference of either outgoing velocity from the closed form, m/s."},
      {"accuracy",
       "The same case in each backend per step: wall ms per simulated s (over every impact parameter's run) against "
       "the largest velocity error from the closed form, m/s for 1 m/s; MuJoCo's soft contact is the baseline."},
      {"crosscheck",
       "Each scenario of models/rigid/crosscheck.h in both models at dt 0.1 ms (where the tolerances hold) and 1 ms "
       "(the service's rate): end velocities' difference over the tip's speed, against the scenario's tolerance, "
       "and each model's momentum, angular momentum and energy change."},
      {"step",
       "One 1 ms step of a row of bodies resting on the marker plane with the tip sweeping across them: median over "
       "300 (quick) or 1000 steps per backend, MuJoCo the baseline in the same run; analytic bodies sleep when at "
       "rest, "
       "analytic_awake is the same with sleep off."}};
  s.plots = {
      {"accuracy",
       "ms_per_sim_s",
       "max_abs_err",
       "wall ms per simulated s",
       "largest velocity error (m/s)",
       {"backend"},
       {},
       {"backend", "mujoco"},
       true,
       false},
      {"step", "bodies", "us_per_step", "bodies", "us per step (median)", {"backend"}, {}, {"backend", "mujoco"}}};
  return s;
}

}  // namespace hcosim::services::bench

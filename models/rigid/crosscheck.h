// The analytic rigid model against MuJoCo on named scenes: the tip, a
// particle of the body's mass (the seed's equal-mass case), hits a body in
// free space, or a body hits another, and both models run on until the
// contact is over. The
// scenarios are shared by the tests, `hcosim bench rigid` and the docs.
#pragma once

#include <string>
#include <vector>

#include "models/rigid/mujoco_world.h"
#include "models/rigid/world.h"

namespace hcosim::models::rigid {

struct Scenario {
  std::string name;
  WorldSpec spec;
  std::vector<Body> bodies;
  Tip tip;
  double duration = 0.1;  // s simulated
  double speed = 1;       // m/s, the scene's speed scale: errors are relative to it
  double tolerance = 0;   // the largest rel_vel_err and rel_angvel_err accepted (docs/rigid.md says why)
};

// head_on, off_centre, grazing, inelastic, spinning, cube_face, cube_edge
// (the tip hits); ball_on_ball, ball_on_cube, cube_on_cube (a body hits another,
// off its centre line; the cube's vertical edge on a face); and
// resting_cube (gravity and the marker plane, no tip).
std::vector<Scenario> scenarios();

struct Divergence {
  double rel_vel_err = 0;     // max |v_analytic - v_mujoco| over bodies and tip / the scene's speed
  double rel_angvel_err = 0;  // max |w_analytic - w_mujoco| over bodies / (speed / body size)
  double position_m = 0;      // max distance between the bodies' centres at the end
  // Changes over the run, relative to the scene's scale (total mass times
  // speed; times body size for L; kinetic energy at that speed): analytic,
  // MuJoCo. MuJoCo's L is its subtree's, about the centre of mass.
  double momentum_drift[2] = {0, 0};
  double angular_momentum_drift[2] = {0, 0};
  double energy_change[2] = {0, 0};  // signed
};

// Runs the scenario in both models at dt (s) and compares the end states.
// At 1e-4 s MuJoCo's contact lasts 0.8 ms; at 1e-3 s it lasts 8 ms, over
// which the bodies turn the contact normal: off-centre hits then differ by
// about 10% (docs/rigid.md).
constexpr double kCrosscheckDt = 1e-4;
Divergence crosscheck(const Scenario& s, double dt = kCrosscheckDt, const MujocoContact& contact = {});

}  // namespace hcosim::models::rigid

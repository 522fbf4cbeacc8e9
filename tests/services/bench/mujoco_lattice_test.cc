// The MuJoCo baseline runs the same lattice: same trajectory as our
// symplectic Euler to within the difference of the two Euler schemes.
#include <gtest/gtest.h>

#include "models/massspring/simulator.h"
#include "services/bench/mujoco_lattice.h"

namespace hcosim::services::bench {

// The lattices the peer runs.
using namespace models::massspring;

namespace {

TEST(MujocoLattice, FollowsTheSameTrajectory) {
  Material m;
  m.b = 0.01;
  m.drag = 0.001;
  Lattice l = make_box(4, 4, 4, 0.01, m);
  anchor_where(l, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
  l.gravity << 0, 0, -9.81;
  const std::vector<PointForce> press{{l.size() - 6, Eigen::Vector3d(0.1, 0, -0.3)}};
  Options o;
  o.integrator = Integrator::symplectic_euler;
  o.dt = 1e-4;
  Simulator ours(l, o);
  MujocoLattice theirs(l, o.dt);
  State s = rest_state(l);
  for (int k = 0; k < 500; ++k) {
    ours.step(s, press);
    theirs.step(press);
  }
  EXPECT_NEAR(theirs.time(), s.t, 1e-12);
  const double moved = (s.x - l.rest).norm();
  EXPECT_GT(moved, 1e-3);
  EXPECT_LT((theirs.positions() - s.x).norm(), 0.01 * moved);
}

TEST(MujocoLattice, RefusesWhatItCannotRun) {
  EXPECT_THROW(MujocoLattice(make_box(2, 2, 2, 0.01, {}), 1e-3, "implicit"), std::invalid_argument);
  // MuJoCo 2.2.2 keeps the tendon Jacobian dense in an int-sized buffer.
  EXPECT_GT(MujocoLattice::data_bytes(make_box(16, 16, 16, 0.01, {})), 2.147e9);
}

}  // namespace
}  // namespace hcosim::services::bench

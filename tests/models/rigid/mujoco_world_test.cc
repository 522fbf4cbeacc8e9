// MuJoCo's contacts rebound at the scene's restitution: the tip's head-on
// hit on a sphere and on a cube's face, and a body dropped flat on the
// plane, for several e, at the cross-check's step and at 1 ms, within
// 0.02; on average over where in a step the contact begins, which moves a
// single hit's rebound by up to 0.05 at 0.1 ms.
#include "models/rigid/mujoco_world.h"

#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "models/rigid/crosscheck.h"

namespace hcosim::models::rigid {
namespace {

// The normal speed after over before, once the contact is over, on
// average over 8 hits each begun a further eighth of a step (`dt`) away
// along `away`; `closing` is the normal speed.
double rebound(const WorldSpec& spec, Body b, Tip t, double dt, const Eigen::Vector3d& away,
               const std::function<double(const MujocoWorld&)>& closing) {
  double sum = 0;
  for (int j = 0; j < 8; ++j) {
    Body bj = b;
    Tip tj = t;
    if (spec.ground)
      bj.x += (j + 0.5) / 8 * dt * away;
    else
      tj.x += (j + 0.5) / 8 * dt * away;
    MujocoWorld w(spec, {bj}, dt);
    w.set_tip(tj);
    const double before = closing(w);
    for (int k = 0; k < int(0.03 / dt); ++k) w.step();
    sum += -closing(w) / before;
  }
  return sum / 8;
}

TEST(RigidMujocoContact, EveryPairReboundsAtItsRestitution) {
  for (const double dt : {kCrosscheckDt, 1e-3})
    for (const Shape shape : {Shape::sphere, Shape::cube})
      for (const double e : {0.1, 0.2, 0.5, 0.8}) {
        SCOPED_TRACE(std::string(shape == Shape::cube ? "cube" : "sphere") + ", e " + std::to_string(e) + ", dt " +
                     std::to_string(dt));
        Body b;
        b.shape = shape, b.size = 0.02, b.mass = 0.1;
        // The tip, 0.1 kg, 2 mm, at 1 m/s onto the body's centre line.
        WorldSpec hit;
        hit.gravity.setZero();
        hit.ground = false;
        hit.tip = Material{e, 0};
        hit.tip_radius = 0.002;
        hit.tip_mass = 0.1;
        Tip t;
        t.x = Eigen::Vector3d(-0.03, 0, 0), t.v = Eigen::Vector3d(1, 0, 0);
        EXPECT_NEAR(rebound(hit, b, t, dt, -Eigen::Vector3d::UnitX(),
                            [](const MujocoWorld& w) { return w.tip().v.x() - w.body(0).v.x(); }),
                    e, 0.02);
        // The body at 1 m/s down onto the plane, no gravity.
        WorldSpec drop = hit;
        drop.ground = true;
        drop.floor = Material{e, 0};
        b.x = Eigen::Vector3d(0, 0, 0.03), b.v = Eigen::Vector3d(0, 0, -1);
        EXPECT_NEAR(rebound(drop, b, {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d::Zero()}, dt, Eigen::Vector3d::UnitZ(),
                            [](const MujocoWorld& w) { return -w.body(0).v.z(); }),
                    e, 0.02);
      }
}

}  // namespace
}  // namespace hcosim::models::rigid

#include "models/rigid/crosscheck.h"

#include <algorithm>
#include <cmath>

namespace hcosim::models::rigid {

namespace {

constexpr double kSize = 0.02, kMass = 0.1, kSpeed = 1.0, kTip = 0.002;

// The tip at x = -6 cm moving +x at 1 m/s, offset (y, z).
Scenario hit(const std::string& name, Shape shape, double y, double z, double e, double mu, double tolerance) {
  Scenario s;
  s.name = name;
  s.spec.gravity.setZero();
  s.spec.ground = false;
  s.spec.drag = Drag{0, 0, 0, 0};
  s.spec.tip = Material{e, mu};
  s.spec.tip_radius = kTip;
  s.spec.tip_mass = kMass;
  Body b;
  b.shape = shape, b.size = kSize, b.mass = kMass;
  s.bodies = {b};
  s.tip.x = Eigen::Vector3d(-0.06, y, z);
  s.tip.v = Eigen::Vector3d(kSpeed, 0, 0);
  s.duration = 0.1;
  s.tolerance = tolerance;
  return s;
}

// Body 1 (a `mover`) at x = -6 cm moving +x at 1 m/s, offset (y, z), hits
// body 0 at rest at the origin; the tip is far away.
Scenario knock(const std::string& name, Shape target, Shape mover, double y, double z, double e, double mu,
               double tolerance) {
  Scenario s = hit(name, target, 0, 0, 1, 0, tolerance);
  s.spec.pair = Material{e, mu};
  Body b;
  b.shape = mover, b.size = kSize, b.mass = kMass;
  b.x = Eigen::Vector3d(-0.06, y, z);
  b.v = Eigen::Vector3d(kSpeed, 0, 0);
  s.bodies.push_back(b);
  s.tip.x = Eigen::Vector3d(1, 1, 1), s.tip.v.setZero();
  return s;
}

}  // namespace

std::vector<Scenario> scenarios() {
  const double reach = kSize + kTip;
  std::vector<Scenario> out;
  out.push_back(hit("head_on", Shape::sphere, 0, 0, 1, 0, 0.01));
  out.push_back(hit("off_centre", Shape::sphere, 0.5 * reach, 0, 1, 0, 0.02));
  out.push_back(hit("grazing", Shape::sphere, 0.95 * reach, 0, 1, 0, 0.03));
  // spinning's hit without friction or spin: what MuJoCo's damped soft
  // contact alone makes of an inelastic hit off the centre line.
  out.push_back(hit("inelastic", Shape::sphere, 0.3 * reach, 0, 0.2, 0, 0.05));
  Scenario spin = hit("spinning", Shape::sphere, 0.3 * reach, 0, 0.2, 0.3, 0.05);
  spin.bodies[0].w = Eigen::Vector3d(0, 0, 30);
  out.push_back(spin);
  out.push_back(hit("cube_face", Shape::cube, 0.5 * kSize, 0, 1, 0, 0.02));
  Scenario edge = hit("cube_edge", Shape::cube, 0.2 * kSize, 0.3 * kSize, 1, 0, 0.03);
  edge.bodies[0].q = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()));
  out.push_back(edge);
  out.push_back(knock("ball_on_ball", Shape::sphere, Shape::sphere, 0.5 * kSize, 0, 1, 0, 0.02));
  out.push_back(knock("ball_on_cube", Shape::cube, Shape::sphere, 0.5 * kSize, 0, 1, 0, 0.02));
  Scenario corner = knock("cube_on_cube", Shape::cube, Shape::cube, 0.3 * kSize, 0, 1, 0, 0.02);
  corner.bodies[1].q = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()));
  out.push_back(corner);
  Scenario rest;
  rest.name = "resting_cube";
  Body cube;
  cube.shape = Shape::cube, cube.size = kSize, cube.mass = kMass;
  cube.x = Eigen::Vector3d(0, 0, kSize);
  rest.bodies = {cube};
  rest.tip.x = Eigen::Vector3d(1, 1, 1);  // far away
  rest.duration = 1.0;
  rest.speed = std::sqrt(9.81 * kSize);  // a fall through its own size
  rest.tolerance = 0.01;
  out.push_back(rest);
  return out;
}

Divergence crosscheck(const Scenario& s, double dt, const MujocoContact& contact) {
  World a(s.spec, s.bodies);
  a.set_tip(s.tip);
  MujocoWorld m(s.spec, s.bodies, dt, contact);
  m.set_tip(s.tip);
  const Eigen::Vector3d p0[2] = {a.momentum(), m.momentum()};
  const Eigen::Vector3d l0[2] = {a.angular_momentum(), m.subtree_angular_momentum()};
  const double e0[2] = {a.kinetic_energy(), m.kinetic_energy()};
  const int steps = int(std::lround(s.duration / dt));
  for (int k = 0; k < steps; ++k) a.step(dt), m.step();
  Divergence d;
  const double speed = s.speed;
  const std::vector<Body> mb = m.bodies();
  d.rel_vel_err = (a.tip().v - m.tip().v).norm() / speed;
  double mass = s.spec.tip_mass, size = 0;
  for (std::size_t i = 0; i < mb.size(); ++i) {
    const Body& ab = a.bodies()[i];
    d.rel_vel_err = std::max(d.rel_vel_err, (ab.v - mb[i].v).norm() / speed);
    d.rel_angvel_err = std::max(d.rel_angvel_err, (ab.w - mb[i].w).norm() / (speed / ab.size));
    d.position_m = std::max(d.position_m, (ab.x - mb[i].x).norm());
    mass += ab.mass, size = std::max(size, ab.size);
  }
  const Eigen::Vector3d p1[2] = {a.momentum(), m.momentum()};
  const Eigen::Vector3d l1[2] = {a.angular_momentum(), m.subtree_angular_momentum()};
  const double e1[2] = {a.kinetic_energy(), m.kinetic_energy()};
  for (int k = 0; k < 2; ++k) {
    d.momentum_drift[k] = (p1[k] - p0[k]).norm() / (mass * speed);
    d.angular_momentum_drift[k] = (l1[k] - l0[k]).norm() / (mass * speed * size);
    d.energy_change[k] = (e1[k] - e0[k]) / (0.5 * mass * speed * speed);
  }
  return d;
}

}  // namespace hcosim::models::rigid

// Rigid bodies of seed 000 §2.1: a cube and a sphere with mass, inertia and
// a pose, and the geometry the collisions and the haptic proxy ask of them.
// Both shapes have an isotropic inertia tensor (a scalar times identity),
// so their rotation needs no gyroscopic term.
#pragma once

#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hcosim::models::rigid {

enum class Shape { sphere, cube };
const char* name(Shape s);
Shape parse_shape(const std::string& s);  // "sphere" or "cube"; throws std::invalid_argument

// A body's constants and state, world frame (the AR marker's), SI units.
struct Body {
  Shape shape = Shape::sphere;
  double size = 0.02;                                     // sphere radius or cube half-edge, m, > 0
  double mass = 0.1;                                      // kg, > 0
  Eigen::Vector3d x = Eigen::Vector3d::Zero();            // centre of mass, m
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // body to world
  Eigen::Vector3d v = Eigen::Vector3d::Zero();            // m/s
  Eigen::Vector3d w = Eigen::Vector3d::Zero();            // rad/s, world frame
  bool sleeping = false;
  double still_s = 0;  // s the body has been slower than the sleep speed
};

// Throws std::invalid_argument naming the bad field.
void check(const Body& b);

// Moment of inertia about the centre (kg m^2): 2/5 m r^2 for a solid
// sphere, 1/6 m a^2 for a cube of edge a.
double inertia(const Body& b);

// Velocity of the body's material point at world position p.
inline Eigen::Vector3d point_velocity(const Body& b, const Eigen::Vector3d& p) { return b.v + b.w.cross(p - b.x); }

// The nearest point of the body's surface grown by `margin` (m, >= 0) to
// world point p: the signed distance (negative inside), that surface point
// and the outward unit normal there. A cube grown by a margin keeps sharp
// edges (a slightly larger box), which errs toward contact.
struct Nearest {
  double distance = 0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
};
Nearest nearest(const Body& b, const Eigen::Vector3d& p, double margin = 0);

// Linear momentum (kg m/s), angular momentum about the world origin
// (kg m^2/s) and kinetic energy (J).
Eigen::Vector3d momentum(const Body& b);
Eigen::Vector3d angular_momentum(const Body& b);
double kinetic_energy(const Body& b);

}  // namespace hcosim::models::rigid

// Where two bodies touch: sphere on sphere, sphere on cube, cube on cube
// (the separating axis test over the 15 axes of two boxes). The contact
// is one point per pair, with the normal of least overlap, which is what
// an impulse per pair and step needs (world.h).
#pragma once

#include <array>

#include <Eigen/Core>

#include "models/rigid/body.h"

namespace hcosim::models::rigid {

struct Contact {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // world, m: midway between the two surfaces
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, out of a, toward b
  double depth = 0;                                   // m: overlap along the normal; negative: a gap
  // Where a cube rests on a cube: up to 4 corners of the touching region
  // (its extreme points along the tangent plane's diagonals), so that a
  // resting contact can hold a face flat; just `point` otherwise.
  std::array<Eigen::Vector3d, 4> support{};
  int supports = 0;
};

// Whether a and b overlap or lie within `gap` (m, >= 0) of it; if so, c
// is their contact. For two cubes the point is the length-weighted centre
// of every edge segment of one that lies inside the other, which is a
// face's overlap centre when faces lie flat on each other, the corner in a
// corner-on-face touch and the crossing in an edge-on-edge one.
bool collide(const Body& a, const Body& b, double gap, Contact& c);

}  // namespace hcosim::models::rigid

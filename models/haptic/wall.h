// A virtual wall: the stiffest thing a stylus can touch, and the classic
// test of haptic rendering stability.
#pragma once

#include <Eigen/Core>

namespace hcosim::models::haptic {

// The half-space behind a plane through `point` with outward unit `normal`.
struct Wall {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // m, world frame
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, pointing out of the wall
  double stiffness = 1000;                            // N/m
  double damping = 0;                                 // N s/m, only while in contact
};

// Penalty force on the stylus at x moving at v: k d n - b (v . n) n while
// the depth d = (point - x) . n is positive, zero outside; *depth gets d
// (clamped at 0). The damping term never pulls the stylus into the wall.
Eigen::Vector3d wall_force(const Wall& wall, const Eigen::Vector3d& x, const Eigen::Vector3d& v, double* depth);

}  // namespace hcosim::models::haptic

// A source's force near the point it was computed at: the intermediate
// representation of haptic rendering (Mark et al. 1996). A device renders
// it at its current position for a source whose answer to this tick is
// late, instead of holding a force computed for an older position.
#pragma once

#include <Eigen/Core>

namespace hcosim::models::haptic {

struct LocalModel {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();     // N, on the stylus at `position`, world frame
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // m, where `force` was computed, world frame
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Zero();  // dF/dx, N/m
  // Unit normal out of the object: a model force pointing into the object
  // along it means the contact has opened (no force). Zero: no such test
  // (a grab pulls the stylus on purpose).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double radius = 0;  // m, >= 0: how far from `position` the expansion holds; 0 holds `force`
};

// How long a free-space model holds after the state it answers: its
// source has bounded its own motion over this long (see covers()).
inline constexpr double kFreeHorizonS = 0.02;  // s

// Whether `m` is a free-space model that reaches x: no force and no
// stiffness, with x closer than `radius` to `position`. A source sends one
// where nothing of it lies within `radius` of the stylus, for the next
// kFreeHorizonS whatever it does meanwhile; there its force is exactly
// zero, and a device needs no newer answer from it to render it.
bool covers(const LocalModel& m, const Eigen::Vector3d& x);

// The force of `m` at x: force + jacobian (x - position), the offset
// limited to `radius`, and zero where a one-sided contact has opened.
// Throws std::invalid_argument for a non-finite x or a negative radius.
Eigen::Vector3d evaluate(const LocalModel& m, const Eigen::Vector3d& x);

// The model of a penalty contact answered at `position` with `force`,
// stiffness `k` (N/m, >= 0) along the unit `normal` and none across it.
LocalModel contact_model(const Eigen::Vector3d& force, const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                         double k, double radius);

}  // namespace hcosim::models::haptic

// A deformable object as the deformable service drives it: touched by the
// haptic interface point every servo tick, advanced at its behavior rate,
// and read as a surface at the visual rate (001 Fig 4, 6).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hcosim::models::deformable {

// The answer to one haptic tick.
struct Touch {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // N, on the stylus, world frame
  bool in_contact = false;
  double depth = 0;      // m, >= 0: how far the HIP is past the rest surface
  double stiffness = 0;  // N/m, >= 0: normal force over depth, the contact's secant stiffness
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, out of the surface touched (zero: no contact)
};

class Object {
 public:
  virtual ~Object() = default;
  // One servo tick of dt seconds with the HIP at `hip` (world frame, m);
  // `grab` keeps the contact while the HIP leaves the object, so that the
  // user can pull it (001 Fig 5b). Throws std::invalid_argument for a
  // non-finite hip or dt.
  virtual Touch touch(double dt, const Eigen::Vector3d& hip, bool grab) = 0;
  // The world box (m, fixed) outside which touch() begins no contact: a
  // HIP outside it touches nothing of the object, but for a contact that
  // began inside and goes on (until the HIP is back out, or in a grab).
  virtual Eigen::AlignedBox3d reach() const = 0;
  // The behavior model's step, s (0: it advances within touch()).
  virtual double behavior_dt() const = 0;
  // One behavior step, in two parts: couple() copies what the behavior
  // model takes from the haptic model (what touch() changed); integrate()
  // then reads nothing touch() changes, so it may run on another thread
  // while touch() does (a service's haptic thread answering the device).
  virtual void couple() = 0;
  virtual void integrate() = 0;
  void advance() { couple(), integrate(); }
  // What the visual surface depends on, copied (cheap: the behavior
  // model's positions that the visual map reads), and the surface it gives:
  // vertex positions (m, world) in the order of triangles(). surface_from
  // reads nothing that touch() or advance() change, so it may run on
  // another thread while they do.
  virtual Eigen::Matrix3Xd cage() const = 0;
  virtual Eigen::Matrix3Xd surface_from(const Eigen::Matrix3Xd& cage) const = 0;
  Eigen::Matrix3Xd surface() const { return surface_from(cage()); }
  virtual const std::vector<Eigen::Vector3i>& triangles() const = 0;
};

}  // namespace hcosim::models::deformable

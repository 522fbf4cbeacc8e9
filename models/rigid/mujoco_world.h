// The rigid scene of world.h in MuJoCo 2.2.2, the cross-check: each body a
// free body with a box or sphere geom, the tip a sphere on three slide
// joints (a particle: it translates, never spins), the marker plane a plane
// geom. The tip-body and body-floor contacts are explicit pairs; body-body
// contacts come from MuJoCo's collision filter; all with world.h's
// materials. Drag and the loads are applied
// through xfrc_applied, and the tip's weight is cancelled there.
//
// Restitution: MuJoCo's contacts are soft (a spring-damper in constraint
// space). With a negative solref (-stiffness, -damping) in units of
// acceleration, a contact of damping ratio z rebounds with
// e = exp(-z pi / sqrt(1 - z^2)); stiffness sets how long a contact lasts
// (`contact_steps` steps per half-period). solimp's impedance d scales the
// spring and damper: its square root scales z (see docs/rigid.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "models/rigid/world.h"

namespace hcosim::models::rigid {

struct MujocoContact {
  double contact_steps = 12;  // steps per contact half-period, >= 2
  double impedance = 0.9;     // solimp d0 = dwidth, in (0, 1)
};

class MujocoWorld {
 public:
  // Throws std::invalid_argument for a bad spec or body and
  // std::runtime_error with MuJoCo's message if it refuses the model.
  MujocoWorld(const WorldSpec& spec, const std::vector<Body>& bodies, double dt, const MujocoContact& contact = {});
  ~MujocoWorld();
  MujocoWorld(const MujocoWorld&) = delete;
  MujocoWorld& operator=(const MujocoWorld&) = delete;

  // One mj_step of the dt given at construction. Throws
  // std::runtime_error if MuJoCo reports a warning.
  void step();

  // As World::set_load: a wrench on body i held over the steps.
  void set_load(std::size_t i, const Eigen::Vector3d& force, const Eigen::Vector3d& torque);

  void set_tip(const Tip& t);
  Tip tip() const;
  std::vector<Body> bodies() const;  // sleeping is always false: MuJoCo 2.2.2 has no sleep
  Body body(std::size_t i) const;    // one of them, without allocating

  // Totals as in World (about the world origin), and MuJoCo's own angular
  // momentum of the whole system about its centre of mass (mj_subtreeVel).
  Eigen::Vector3d momentum() const;
  Eigen::Vector3d angular_momentum() const;
  Eigen::Vector3d subtree_angular_momentum() const;
  double kinetic_energy() const;

  static std::string xml(const WorldSpec& spec, const std::vector<Body>& bodies, double dt,
                         const MujocoContact& contact);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hcosim::models::rigid

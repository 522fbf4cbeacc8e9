// The same lattice in MuJoCo 2.2.2, the baseline the benchmark compares
// against: each free mass is a body with three slide joints, each anchored
// mass a fixed body, each spring a spatial tendon between two sites with the
// spring's stiffness and damping and its rest length as spring length, and
// the drag a joint damping. Contacts are disabled. The model is loaded from
// an in-memory XML file.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/massspring/forces.h"
#include "models/massspring/lattice.h"

namespace hcosim::services::bench {

class MujocoLattice {
 public:
  // `integrator`: MuJoCo's "Euler" (semi-implicit) or "RK4". Throws
  // std::invalid_argument for a bad lattice and std::runtime_error with
  // MuJoCo's message if it refuses the model.
  MujocoLattice(const models::massspring::Lattice& lattice, double dt, const std::string& integrator = "Euler");
  ~MujocoLattice();
  MujocoLattice(const MujocoLattice&) = delete;
  MujocoLattice& operator=(const MujocoLattice&) = delete;

  // One mj_step of dt with `loads` applied as body forces. Throws
  // std::runtime_error if MuJoCo reports a warning (instability, stack).
  void step(const std::vector<models::massspring::PointForce>& loads);

  Eigen::Matrix3Xd positions() const;  // m, every mass
  double time() const;                 // s

  // Bytes MuJoCo 2.2.2 allocates for mjData, dominated by the tendon
  // Jacobian (tendons x dofs, stored dense in this version).
  static double data_bytes(const models::massspring::Lattice& lattice);

  // The generated MJCF text (for the docs and for debugging).
  static std::string xml(const models::massspring::Lattice& lattice, double dt, const std::string& integrator);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hcosim::services::bench

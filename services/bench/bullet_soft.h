// The same solid in Bullet 3.24's btSoftBody (libbullet-dev), the soft
// body of the peers haptic surgical simulators build on (AMBF): a node per
// mass, a link along every tetrahedron edge with linear stiffness
// coefficient kLST (in (0, 1]: the share of a link's error its position
// solver removes per iteration, not a material constant), anchored nodes
// of no inverse mass, damping kDP; no gravity, no air, no collisions.
// Stepped alone in a btSoftRigidDynamicsWorld at a fixed dt, point loads
// through addForce.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "models/massspring/forces.h"

namespace hcosim::services::bench {

struct BulletSoftSettings {
  double stiffness = 1;  // kLST, (0, 1]
  int iterations = 4;    // position solver iterations per step
  double damping = 0;    // kDP, [0, 1]
  double dt = 1e-3;      // s
};

class BulletSoft {
 public:
  // `mass` per node (kg, > 0 unless anchored). Throws std::invalid_argument
  // for sizes that disagree or settings out of range.
  BulletSoft(const Eigen::Matrix3Xd& rest, const std::vector<std::array<int, 4>>& tets, const Eigen::VectorXd& mass,
             const std::vector<std::uint8_t>& anchored, const BulletSoftSettings& settings);
  ~BulletSoft();
  BulletSoft(const BulletSoft&) = delete;
  BulletSoft& operator=(const BulletSoft&) = delete;

  void step(const std::vector<models::massspring::PointForce>& loads);
  Eigen::Matrix3Xd positions() const;  // m, every node

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hcosim::services::bench

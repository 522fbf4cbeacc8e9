#include "services/bench/bullet_soft.h"

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

namespace hcosim::services::bench {

struct BulletSoft::Impl {
  btSoftBodyRigidBodyCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::unique_ptr<btSoftBody> body;
  double dt = 0;

  ~Impl() {
    if (body) world.removeSoftBody(body.get());
  }
};

BulletSoft::BulletSoft(const Eigen::Matrix3Xd& rest, const std::vector<std::array<int, 4>>& tets,
                       const Eigen::VectorXd& mass, const std::vector<std::uint8_t>& anchored,
                       const BulletSoftSettings& s)
    : impl_(std::make_unique<Impl>()) {
  const int n = int(rest.cols());
  if (mass.size() != n || int(anchored.size()) != n)
    throw std::invalid_argument("bullet soft body: mass and anchored need one entry per node");
  if (!(s.stiffness > 0 && s.stiffness <= 1) || s.iterations < 1 || !(s.damping >= 0 && s.damping <= 1) || !(s.dt > 0))
    throw std::invalid_argument("bullet soft body: stiffness in (0, 1], iterations >= 1, damping in [0, 1], dt > 0");
  Impl& m = *impl_;
  m.dt = s.dt;
  btSoftBodyWorldInfo& info = m.world.getWorldInfo();
  info.m_gravity.setZero();
  info.air_density = 0;
  info.m_sparsesdf.Initialize();
  std::vector<btVector3> x(n);
  std::vector<btScalar> w(n);
  for (int i = 0; i < n; ++i) {
    x[i] = btVector3(rest(0, i), rest(1, i), rest(2, i));
    w[i] = anchored[i] ? 0 : mass[i];  // no mass: Bullet's anchor
  }
  m.body = std::make_unique<btSoftBody>(&info, n, x.data(), w.data());
  btSoftBody& b = *m.body;
  b.m_materials[0]->m_kLST = btScalar(s.stiffness);
  std::set<std::pair<int, int>> edges;
  for (const auto& t : tets)
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < p; ++q) {
        if (t[p] < 0 || t[p] >= n || t[q] < 0 || t[q] >= n)
          throw std::invalid_argument("bullet soft body: a tetrahedron's corner is out of range");
        edges.emplace(std::min(t[p], t[q]), std::max(t[p], t[q]));
      }
  for (const auto& [i, j] : edges) b.appendLink(i, j);
  b.m_cfg.piterations = s.iterations;
  b.m_cfg.kDP = btScalar(s.damping);
  b.m_cfg.collisions = 0;
  m.world.addSoftBody(&b);
}

BulletSoft::~BulletSoft() = default;

void BulletSoft::step(const std::vector<models::massspring::PointForce>& loads) {
  btSoftBody& b = *impl_->body;
  for (const models::massspring::PointForce& p : loads)
    b.addForce(btVector3(p.force.x(), p.force.y(), p.force.z()), p.mass);
  impl_->world.stepSimulation(btScalar(impl_->dt), 0);
}

Eigen::Matrix3Xd BulletSoft::positions() const {
  const btSoftBody& b = *impl_->body;
  Eigen::Matrix3Xd x(3, b.m_nodes.size());
  for (int i = 0; i < b.m_nodes.size(); ++i)
    x.col(i) = Eigen::Vector3d(b.m_nodes[i].m_x.x(), b.m_nodes[i].m_x.y(), b.m_nodes[i].m_x.z());
  return x;
}

}  // namespace hcosim::services::bench

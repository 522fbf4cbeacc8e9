// Coulomb friction for a surface proxy (the god-object of Zilles and
// Salisbury 1995 with the friction cone of Salisbury et al. 1995, as in
// CHAI3D's finger-proxy): the proxy, held on an object's surface while the
// device point (HIP) is pushed in, follows the HIP sideways only as far as
// keeps the coupling force inside the friction cone. With a spring between
// proxy and HIP the force's tangential part over its normal part is the
// HIP's tangential offset over its depth, so the cone is a bound on that
// offset: the proxy sticks while the offset is within mu_static times the
// depth, and once slipping it trails the HIP at mu_dynamic times the depth
// until the HIP comes back inside that cone.
#pragma once

#include <Eigen/Core>

namespace hcosim::models::haptic {

// Coefficients of one contact pair, dimensionless, >= 0; dynamic <= static.
struct Friction {
  double static_mu = 0.3;
  double dynamic_mu = 0.3;
};

// Throws std::invalid_argument naming the coefficient that is negative,
// not finite, or a dynamic one above the static one.
void check(const Friction& f);

class FrictionCone {
 public:
  explicit FrictionCone(Friction f);  // check()s f

  // The proxy on the tangent plane through `proxy` (outward unit normal
  // `n`, world, m) for HIP `h`: where friction lets it go this tick toward
  // h's projection on that plane. An object's proxy puts the result back
  // on its (curved) surface. A HIP outside the surface (depth <= 0) ends
  // the contact: the proxy is the HIP itself (no force), and the next
  // contact starts stuck. Preconditions: n is a unit vector, all finite.
  Eigen::Vector3d slide(const Eigen::Vector3d& proxy, const Eigen::Vector3d& n, const Eigen::Vector3d& h);

  // The same rule on a coupling force of any law: `force` (N, on the
  // device, pushing it out along the outward unit normal n) is kept inside
  // the cone of the state the contact is in; `keep` is the share of the
  // proxy's tangential offset from the HIP that stays (1: stuck), so that
  // the next tick's force lies on the dynamic rim for a coupling linear in
  // that offset. A force that does not push (force . n <= 0) is returned
  // as it is, stuck. Preconditions: n is a unit vector, all finite.
  struct Grip {
    Eigen::Vector3d force;
    double keep = 1;
  };
  Grip grip(const Eigen::Vector3d& force, const Eigen::Vector3d& n);

  // The contact ended (the object's own test): the next one starts stuck.
  void release() { slipping_ = false; }

  bool slipping() const { return slipping_; }
  const Friction& friction() const { return f_; }

 private:
  Friction f_;
  bool slipping_ = false;
};

}  // namespace hcosim::models::haptic

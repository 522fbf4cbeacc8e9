// God-object haptic rendering (Zilles and Salisbury 1995) for one convex
// body: a proxy point that stays on the surface (grown by the tip radius)
// while the device's haptic interface point (HIP) goes inside, moving each
// tick to the point of its constraint plane nearest the HIP. The device is
// pulled toward the proxy by a spring (coupling.h). Unlike the nearest surface point,
// the proxy never jumps to the far side of the body when the HIP is pushed
// past its middle. With friction the proxy sticks to the face until the
// pull leaves the friction cone, and trails on its rim while slipping
// (models/haptic/friction.h).
#pragma once

#include <Eigen/Core>

#include "models/haptic/friction.h"
#include "models/rigid/body.h"

namespace hcosim::models::rigid {

class Proxy {
 public:
  // `f`: the stylus against this body; {0, 0} is frictionless.
  explicit Proxy(haptic::Friction f) : cone_(f) {}

  // The proxy for HIP h (world, m) against body b grown by tip_radius;
  // the HIP itself when it is outside. The proxy is kept in the body's
  // frame, so it rides along when the body moves. Throws
  // std::invalid_argument for a non-finite h.
  Eigen::Vector3d update(const Body& b, double tip_radius, const Eigen::Vector3d& h);

  bool in_contact() const { return contact_; }
  bool slipping() const { return cone_.slipping(); }

 private:
  haptic::FrictionCone cone_;
  bool contact_ = false;
  Eigen::Vector3d local_ = Eigen::Vector3d::Zero();  // proxy, body frame
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();   // last free HIP, world
};

}  // namespace hcosim::models::rigid

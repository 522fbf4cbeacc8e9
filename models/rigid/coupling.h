// Virtual coupling (Colgate, Stanley and Brown 1995) between the haptic
// device and one rigid body: a spring-damper between the device's point
// (HIP) and the body's god-object proxy (proxy.h). The body receives the
// opposite of the force the device is given, at the proxy, so what the hand
// feels is what moves the body: pushing a cube costs its inertia and its
// friction on the marker plane, no more. The damper acts along the contact
// normal only, so that a sliding stroke's tangential force is friction's
// alone, and it grows with depth (Hunt and Crossley 1975), so that a
// contact starts with the spring alone and no kick; the coupling never
// pulls.
#pragma once

#include <Eigen/Core>

#include "models/haptic/friction.h"
#include "models/rigid/body.h"
#include "models/rigid/proxy.h"

namespace hcosim::models::rigid {

struct CouplingSpec {
  double stiffness = 500;  // N/m, > 0
  double damping = 1;      // N s/m per mm of depth, >= 0, along the contact normal
  double max_force = 3.3;  // N, > 0: the force's norm is clamped here (the PHANToM Omni's peak)
};

// Throws std::invalid_argument naming the bad field.
void check(const CouplingSpec& s);

// One tick's touch of the stylus on a body.
struct Touch {
  bool contact = false;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N, on the device, world
  Eigen::Vector3d proxy = Eigen::Vector3d::Zero();   // m, world: the HIP itself when free
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, out of the body at the proxy; zero when free
  double depth = 0;                                  // m, |proxy - HIP|
  bool clamped = false;                              // the force is at max_force
};

// The load that delivers a run of touches' impulses to the body.
struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // N, through the body's centre
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // N m, about it
};

class Coupling {
 public:
  // `f`: the stylus against this body; {0, 0} is frictionless. Throws
  // std::invalid_argument for a bad spec or friction.
  Coupling(const CouplingSpec& spec, haptic::Friction f);

  // The touch of HIP h moving at hv (world, m and m/s) on body b grown by
  // tip_radius (m), its force standing for the next held_s (s, >= 0) of
  // the device's time: the opposite impulse, -force held_s at the proxy,
  // is added to what the body is owed. Throws std::invalid_argument for a
  // non-finite h or hv or a negative held_s.
  Touch touch(const Body& b, double tip_radius, const Eigen::Vector3d& h, const Eigen::Vector3d& hv, double held_s);

  // The constant wrench on body b over the next dt (s, > 0) that delivers
  // what it is owed, which is then cleared. b is the body the touches were
  // made on (its centre is where the torque is taken).
  Wrench load(const Body& b, double dt);

  bool slipping() const { return proxy_.slipping(); }

 private:
  CouplingSpec spec_;
  Proxy proxy_;
  Eigen::Vector3d impulse_ = Eigen::Vector3d::Zero();  // N s, owed to the body
  Eigen::Vector3d moment_ = Eigen::Vector3d::Zero();   // N s m, about the world origin
};

}  // namespace hcosim::models::rigid

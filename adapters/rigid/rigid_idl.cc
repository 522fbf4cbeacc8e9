#include "adapters/rigid/rigid_idl.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "adapters/device/haptic_idl.h"

namespace hcosim::adapters::rigid {

RigidBodyState body_state(const std::string& name, const StepStamp& stamp, const models::rigid::Body& b,
                          const char* backend) {
  RigidBodyState s;
  s.body(name);
  s.stamp(stamp);
  s.shape(models::rigid::name(b.shape));
  s.backend(backend);
  s.pose().position(adapters::device::to_idl(b.x));
  s.pose().orientation().w(b.q.w()), s.pose().orientation().x(b.q.x());
  s.pose().orientation().y(b.q.y()), s.pose().orientation().z(b.q.z());
  s.linear_velocity(adapters::device::to_idl(b.v));
  s.angular_velocity(adapters::device::to_idl(b.w));
  s.sleeping(b.sleeping);
  return s;
}

RigidDivergence divergence(const std::string& name, const StepStamp& stamp, const models::rigid::Body& a,
                           const models::rigid::Body& m) {
  RigidDivergence d;
  d.body(name);
  d.stamp(stamp);
  d.position_m((a.x - m.x).norm());
  // q and -q are one rotation: the angle between them uses |dot|.
  d.orientation_rad(2 * std::acos(std::min(1.0, std::abs(a.q.normalized().dot(m.q.normalized())))));
  d.velocity_m_s((a.v - m.v).norm());
  d.angular_velocity_rad_s((a.w - m.w).norm());
  return d;
}

}  // namespace hcosim::adapters::rigid

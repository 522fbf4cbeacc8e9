#include "adapters/device/haptic_idl.h"

#include <algorithm>

namespace hcosim::adapters::device {

HapticState haptic_state(const std::string& device, std::uint64_t seq, const StepStamp& stamp, const Frame& f,
                         const Eigen::Vector3d& rendered) {
  HapticState s;
  s.device(device);
  s.seq(seq);
  s.stamp(stamp);
  s.device_time_s(f.time_s);
  s.position(to_idl(f.position));
  s.velocity(to_idl(f.velocity));
  s.orientation().w(f.orientation.w()), s.orientation().x(f.orientation.x());
  s.orientation().y(f.orientation.y()), s.orientation().z(f.orientation.z());
  s.buttons(f.buttons);
  s.rendered_force(to_idl(rendered));
  return s;
}

Feel contact_feel(const Eigen::Vector3d& force, const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                  double k, double depth, double radius) {
  const models::haptic::LocalModel m = models::haptic::contact_model(force, position, normal, k, radius);
  Feel f;
  f.force = force;
  f.in_contact = true;
  f.depth = depth;
  f.stiffness = k;
  f.position = position;
  f.jacobian = m.jacobian;
  f.normal = normal;
  f.radius = radius;
  return f;
}

ForceFeedback force_feedback(const std::string& source, const std::string& device, std::uint64_t seq,
                             const StepStamp& stamp, const Feel& feel) {
  ForceFeedback f;
  f.source(source);
  f.device(device);
  f.answers_seq(seq);
  f.stamp(stamp);
  f.force(to_idl(feel.force));
  f.in_contact(feel.in_contact);
  f.penetration_m(feel.depth);
  f.stiffness_n_per_m(feel.stiffness);
  f.position(to_idl(feel.position));
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) f.jacobian()[std::size_t(3 * r + c)] = feel.jacobian(r, c);
  f.normal(to_idl(feel.normal));
  f.valid_radius_m(feel.radius);
  return f;
}

Feel free_feel(const Eigen::Vector3d& position, double clearance) {
  Feel f;
  f.position = position;
  // Half a metre is far more than a hand travels within the horizon.
  f.radius = std::clamp(clearance, 0.0, 0.5);
  return f;
}

bool answer_covered(const Feel& last, std::uint64_t last_seq, const Eigen::Vector3d& hip, std::uint64_t seq,
                    double servo_dt) {
  if (last.in_contact || !(last.radius > 0) || seq < last_seq) return false;
  return double(seq - last_seq) * servo_dt <= 0.5 * models::haptic::kFreeHorizonS &&
         (hip - last.position).norm() < last.radius;
}

models::haptic::LocalModel local_model(const ForceFeedback& f) {
  models::haptic::LocalModel m;
  m.force = from_idl(f.force());
  m.position = from_idl(f.position());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.jacobian(r, c) = f.jacobian()[std::size_t(3 * r + c)];
  m.normal = from_idl(f.normal());
  m.radius = f.valid_radius_m();
  return m;
}

}  // namespace hcosim::adapters::device

#include "device/haptic_idl.h"

namespace hcosim::device {

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
  return f;
}

}  // namespace hcosim::device

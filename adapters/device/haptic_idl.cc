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

}  // namespace hcosim::device

#include "adapters/validate.h"

#include <cmath>

#include <Eigen/Core>

namespace hcosim::adapters {
namespace {

using Problem = std::optional<std::string>;

std::string fmt(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "+Inf" : "-Inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

Problem check(const char* field, double v, double limit) {
  if (!std::isfinite(v)) return std::string(field) + " is " + fmt(v);
  if (std::abs(v) > limit) return std::string(field) + " = " + fmt(v) + " exceeds " + fmt(limit);
  return std::nullopt;
}

Problem check(const std::string& field, const Vec3& v, double limit) {
  const double c[3] = {v.x(), v.y(), v.z()};
  const char* axis[3] = {".x", ".y", ".z"};
  for (int i = 0; i < 3; ++i)
    if (auto p = check((field + axis[i]).c_str(), c[i], limit)) return p;
  return std::nullopt;
}

Problem check(const std::string& field, const Quat& q) {
  const double c[4] = {q.w(), q.x(), q.y(), q.z()};
  for (double x : c)
    if (!std::isfinite(x)) return field + " has a non-finite component";
  const double n = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]);
  if (std::abs(n - 1.0) > kQuatNormTol) return field + " is not a unit quaternion (norm " + fmt(n) + ")";
  return std::nullopt;
}

Problem check(const StepStamp& s) {
  if (s.sim_time_ns() < 0) return "stamp.sim_time_ns is negative";
  return std::nullopt;
}

// First problem of a list of checks, in order.
template <class... P>
Problem first(P&&... problems) {
  Problem out;
  ((out = out ? out : std::forward<P>(problems)), ...);
  return out;
}

template <class Seq>
Problem check_floats(const char* field, const Seq& seq, double limit) {
  // One vectorised pass first (meshes carry 10^5 floats a sample, 5x faster
  // than the loop below); only a bad sample pays for finding which float it was.
  using T = typename Seq::value_type;
  if (seq.empty()) return std::nullopt;
  const T largest = Eigen::Map<const Eigen::Array<T, Eigen::Dynamic, 1>>(seq.data(), Eigen::Index(seq.size()))
                        .abs()
                        .template maxCoeff<Eigen::PropagateNaN>();
  if (double(largest) <= limit) return std::nullopt;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    if (!std::isfinite(seq[i]) || std::abs(seq[i]) > limit)
      return std::string(field) + "[" + std::to_string(i) + "] = " + fmt(seq[i]) +
             (std::isfinite(seq[i]) ? " exceeds " + fmt(limit) : "");
  }
  return std::nullopt;
}

}  // namespace

Problem validate(const HapticState& s) {
  return first(check(s.stamp()), check("device_time_s", s.device_time_s(), 1e9),
               check("position", s.position(), kMaxDistanceM), check("velocity", s.velocity(), kMaxSpeedMps),
               check("orientation", s.orientation()), check("rendered_force", s.rendered_force(), kMaxForceN));
}

Problem validate(const ForceFeedback& s) {
  Problem p = first(check(s.stamp()), check("force", s.force(), kMaxForceN),
                    check("penetration_m", s.penetration_m(), kMaxDistanceM),
                    check("stiffness_n_per_m", s.stiffness_n_per_m(), kMaxStiffnessNpm));
  if (p) return p;
  if (s.penetration_m() < 0) return std::string("penetration_m is negative");
  if (s.stiffness_n_per_m() < 0) return std::string("stiffness_n_per_m is negative");
  // The local model: a device evaluates it every tick an answer is late.
  p = first(check("position", s.position(), kMaxDistanceM), check("normal", s.normal(), 2.0),
            check("valid_radius_m", s.valid_radius_m(), kMaxDistanceM));
  if (p) return p;
  for (std::size_t i = 0; i < s.jacobian().size(); ++i)
    if (auto q = check(("jacobian[" + std::to_string(i) + "]").c_str(), s.jacobian()[i], kMaxStiffnessNpm)) return q;
  if (s.valid_radius_m() < 0) return std::string("valid_radius_m is negative");
  const double n = std::hypot(s.normal().x(), s.normal().y(), s.normal().z());
  if (n != 0 && std::abs(n - 1) > 1e-6)
    return "normal is neither zero nor a unit vector (length " + std::to_string(n) + ")";
  return std::nullopt;
}

Problem validate(const MarkerPose& s) {
  Problem p = first(check(s.stamp()), check("tag_in_camera.position", s.tag_in_camera().position(), kMaxDistanceM),
                    check("tag_in_camera.orientation", s.tag_in_camera().orientation()),
                    check("tag_size_m", s.tag_size_m(), kMaxDistanceM),
                    check("reprojection_error_px", s.reprojection_error_px(), 1e6),
                    check("decision_margin", s.decision_margin(), 1e6), check("latency_ms", s.latency_ms(), 1e6));
  if (p) return p;
  if (s.tag_size_m() <= 0) return std::string("tag_size_m must be positive");
  return std::nullopt;
}

Problem validate(const CameraFrame& s) {
  if (auto p = check(s.stamp())) return p;
  const std::string enc = s.encoding().to_string();
  const std::size_t channels = enc == "bgr8" ? 3 : enc == "mono8" ? 1 : 0;
  if (channels == 0) return "encoding '" + enc + "' is not bgr8 or mono8";
  if (s.width() == 0 || s.height() == 0) return std::string("width and height must be positive");
  const std::size_t pixels = std::size_t(s.width()) * s.height();
  if (pixels > kMaxPixels) return "image of " + std::to_string(pixels) + " pixels exceeds the limit";
  if (s.data().size() != pixels * channels)
    return "data has " + std::to_string(s.data().size()) +
           " bytes, expected width*height*channels = " + std::to_string(pixels * channels);
  const double k[4] = {s.fx(), s.fy(), s.cx(), s.cy()};
  for (double x : k)
    if (!std::isfinite(x)) return std::string("intrinsics are not finite");
  if (s.fx() <= 0 || s.fy() <= 0) return std::string("focal lengths must be positive");
  return check_floats("distortion", s.distortion(), 1e3);
}

Problem validate(const RigidBodyState& s) {
  return first(check(s.stamp()), check("pose.position", s.pose().position(), kMaxDistanceM),
               check("pose.orientation", s.pose().orientation()),
               check("linear_velocity", s.linear_velocity(), kMaxSpeedMps),
               check("angular_velocity", s.angular_velocity(), kMaxAngularRadps));
}

Problem validate(const RigidDivergence& s) {
  const double d[4] = {s.position_m(), s.orientation_rad(), s.velocity_m_s(), s.angular_velocity_rad_s()};
  for (double x : d)
    if (!(x >= 0)) return "a divergence is " + fmt(x) + ", not a norm";
  return first(check(s.stamp()), check("position_m", s.position_m(), 2 * kMaxDistanceM),
               check("orientation_rad", s.orientation_rad(), 4),
               check("velocity_m_s", s.velocity_m_s(), 2 * kMaxSpeedMps),
               check("angular_velocity_rad_s", s.angular_velocity_rad_s(), 2 * kMaxAngularRadps));
}

Problem validate(const DeformedMesh& s) {
  if (auto p = check(s.stamp())) return p;
  if (s.positions().size() % 3 != 0) return std::string("positions length is not a multiple of 3");
  if (!s.normals().empty() && s.normals().size() != s.positions().size())
    return std::string("normals and positions differ in length");
  return first(check_floats("positions", s.positions(), kMaxDistanceM),
               check_floats("normals", s.normals(), 1.0 + 1e-3));
}

Problem validate(const MeshTopology& s) {
  if (s.triangles().size() % 3 != 0) return std::string("triangles length is not a multiple of 3");
  for (std::size_t i = 0; i < s.triangles().size(); ++i)
    if (s.triangles()[i] >= s.vertex_count())
      return "triangles[" + std::to_string(i) + "] = " + std::to_string(s.triangles()[i]) +
             " is not below vertex_count " + std::to_string(s.vertex_count());
  return std::nullopt;
}

Problem validate(const ServiceStatus& s) {
  return first(check(s.stamp()), check("rate_target_hz", s.rate_target_hz(), 1e9),
               check("rate_achieved_hz", s.rate_achieved_hz(), 1e9));
}

Problem validate(const ClockTick& s) {
  if (s.step_ns() <= 0) return std::string("step_ns must be positive");
  if (s.sim_time_ns() < 0) return std::string("sim_time_ns is negative");
  return std::nullopt;
}

Problem validate(const StepDone& s) {
  if (s.service().size() == 0) return std::string("service name is empty");
  return std::nullopt;
}

}  // namespace hcosim::adapters

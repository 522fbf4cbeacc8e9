#include "adapters/idl_json.h"

#include "adapters/json.h"

namespace hcosim::adapters {
namespace {

template <std::size_t N>
std::string text(const eprosima::fastrtps::fixed_string<N>& s) {
  return std::string(s.c_str(), s.size());
}

// A sequence or array of numbers; floats as their shortest text.
template <class Seq>
Json numbers(const Seq& seq) {
  Json a = Json::array();
  for (const auto& x : seq) {
    if constexpr (std::is_same_v<std::decay_t<decltype(x)>, float>)
      a.push_back(json_float(x));
    else
      a.push_back(x);
  }
  return a;
}

}  // namespace

Json json_of(const Vec3& v) {
  Json j;
  j["x"] = v.x();
  j["y"] = v.y();
  j["z"] = v.z();
  return j;
}

Json json_of(const Quat& q) {
  Json j;
  j["w"] = q.w();
  j["x"] = q.x();
  j["y"] = q.y();
  j["z"] = q.z();
  return j;
}

Json json_of(const Transform& p) {
  Json j;
  j["position"] = json_of(p.position());
  j["orientation"] = json_of(p.orientation());
  return j;
}

Json json_of(const StepStamp& s) {
  Json j;
  j["step"] = s.step();
  j["sim_time_ns"] = s.sim_time_ns();
  j["wall_time_ns"] = s.wall_time_ns();
  return j;
}

Json json_of(const HapticState& s) {
  Json j;
  j["device"] = text(s.device());
  j["seq"] = s.seq();
  j["stamp"] = json_of(s.stamp());
  j["device_time_s"] = s.device_time_s();
  j["position"] = json_of(s.position());
  j["velocity"] = json_of(s.velocity());
  j["orientation"] = json_of(s.orientation());
  j["buttons"] = s.buttons();
  j["rendered_force"] = json_of(s.rendered_force());
  return j;
}

Json json_of(const ForceFeedback& s) {
  Json j;
  j["source"] = text(s.source());
  j["device"] = text(s.device());
  j["answers_seq"] = s.answers_seq();
  j["stamp"] = json_of(s.stamp());
  j["force"] = json_of(s.force());
  j["in_contact"] = s.in_contact();
  j["penetration_m"] = s.penetration_m();
  j["stiffness_n_per_m"] = s.stiffness_n_per_m();
  j["position"] = json_of(s.position());
  j["jacobian"] = numbers(s.jacobian());
  j["normal"] = json_of(s.normal());
  j["valid_radius_m"] = s.valid_radius_m();
  return j;
}

Json json_of(const MarkerPose& s) {
  Json j;
  j["camera"] = text(s.camera());
  j["tag_id"] = s.tag_id();
  j["family"] = text(s.family());
  j["stamp"] = json_of(s.stamp());
  j["frame"] = s.frame();
  j["tag_in_camera"] = json_of(s.tag_in_camera());
  j["tag_size_m"] = s.tag_size_m();
  j["reprojection_error_px"] = s.reprojection_error_px();
  j["decision_margin"] = s.decision_margin();
  j["latency_ms"] = s.latency_ms();
  return j;
}

Json json_of(const CameraFrame& s) {
  Json j;
  j["camera"] = text(s.camera());
  j["stamp"] = json_of(s.stamp());
  j["frame"] = s.frame();
  j["width"] = s.width();
  j["height"] = s.height();
  j["encoding"] = text(s.encoding());
  j["fx"] = s.fx();
  j["fy"] = s.fy();
  j["cx"] = s.cx();
  j["cy"] = s.cy();
  j["distortion"] = numbers(s.distortion());
  j["data_bytes"] = s.data().size();
  return j;
}

Json json_of(const RigidBodyState& s) {
  Json j;
  j["body"] = text(s.body());
  j["stamp"] = json_of(s.stamp());
  j["shape"] = text(s.shape());
  j["backend"] = text(s.backend());
  j["pose"] = json_of(s.pose());
  j["linear_velocity"] = json_of(s.linear_velocity());
  j["angular_velocity"] = json_of(s.angular_velocity());
  j["sleeping"] = s.sleeping();
  return j;
}

Json json_of(const RigidDivergence& s) {
  Json j;
  j["body"] = text(s.body());
  j["stamp"] = json_of(s.stamp());
  j["position_m"] = s.position_m();
  j["orientation_rad"] = s.orientation_rad();
  j["velocity_m_s"] = s.velocity_m_s();
  j["angular_velocity_rad_s"] = s.angular_velocity_rad_s();
  return j;
}

Json json_of(const DeformedMesh& s) {
  Json j;
  j["mesh"] = text(s.mesh());
  j["stamp"] = json_of(s.stamp());
  j["topology_version"] = s.topology_version();
  j["positions"] = numbers(s.positions());
  j["normals"] = numbers(s.normals());
  return j;
}

Json json_of(const MeshTopology& s) {
  Json j;
  j["mesh"] = text(s.mesh());
  j["topology_version"] = s.topology_version();
  j["vertex_count"] = s.vertex_count();
  j["triangles"] = numbers(s.triangles());
  return j;
}

Json json_of(const ServiceStatus& s) {
  Json j;
  j["service"] = text(s.service());
  j["stamp"] = json_of(s.stamp());
  j["pid"] = s.pid();
  j["mode"] = text(s.mode());
  j["state"] = text(s.state());
  j["rate_target_hz"] = s.rate_target_hz();
  j["rate_achieved_hz"] = s.rate_achieved_hz();
  j["jitter_p50_us"] = s.jitter_p50_us();
  j["jitter_p99_us"] = s.jitter_p99_us();
  j["step_p99_us"] = s.step_p99_us();
  j["steps"] = s.steps();
  j["overruns"] = s.overruns();
  j["samples_rejected"] = s.samples_rejected();
  j["last_rejection"] = text(s.last_rejection());
  j["outputs_skipped"] = s.outputs_skipped();
  j["outputs_shed"] = s.outputs_shed();
  j["scheduling"] = text(s.scheduling());
  j["in_tick_ratio"] = s.in_tick_ratio();
  j["force_error_p99_n"] = s.force_error_p99_n();
  return j;
}

Json json_of(const ClockTick& s) {
  Json j;
  j["step"] = s.step();
  j["sim_time_ns"] = s.sim_time_ns();
  j["step_ns"] = s.step_ns();
  j["last"] = s.last();
  return j;
}

Json json_of(const StepDone& s) {
  Json j;
  j["service"] = text(s.service());
  j["step"] = s.step();
  return j;
}
}  // namespace hcosim::adapters

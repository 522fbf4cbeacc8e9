#include "adapters/idl_json.h"

namespace hcosim::adapters {
namespace {

template <class Seq>
void write_seq(Json& j, const Seq& seq) {
  j.begin_array();
  for (const auto& x : seq) j.value(x);
  j.end_array();
}

template <std::size_t N>
void write_str(Json& j, const char* k, const eprosima::fastrtps::fixed_string<N>& s) {
  j.key(k).value(std::string_view(s.c_str(), s.size()));
}

}  // namespace

void write_json(Json& j, const Vec3& v) {
  j.begin_object().key("x").value(v.x()).key("y").value(v.y()).key("z").value(v.z()).end_object();
}

void write_json(Json& j, const Quat& q) {
  j.begin_object().key("w").value(q.w()).key("x").value(q.x()).key("y").value(q.y());
  j.key("z").value(q.z()).end_object();
}

void write_json(Json& j, const Transform& p) {
  j.begin_object().key("position");
  write_json(j, p.position());
  j.key("orientation");
  write_json(j, p.orientation());
  j.end_object();
}

void write_json(Json& j, const StepStamp& s) {
  j.begin_object().key("step").value(s.step()).key("sim_time_ns").value(s.sim_time_ns());
  j.key("wall_time_ns").value(s.wall_time_ns()).end_object();
}

void write_json(Json& j, const HapticState& s) {
  j.begin_object();
  write_str(j, "device", s.device());
  j.key("seq").value(s.seq()).key("stamp");
  write_json(j, s.stamp());
  j.key("device_time_s").value(s.device_time_s()).key("position");
  write_json(j, s.position());
  j.key("velocity");
  write_json(j, s.velocity());
  j.key("orientation");
  write_json(j, s.orientation());
  j.key("buttons").value(s.buttons()).key("rendered_force");
  write_json(j, s.rendered_force());
  j.end_object();
}

void write_json(Json& j, const ForceFeedback& s) {
  j.begin_object();
  write_str(j, "source", s.source());
  write_str(j, "device", s.device());
  j.key("answers_seq").value(s.answers_seq()).key("stamp");
  write_json(j, s.stamp());
  j.key("force");
  write_json(j, s.force());
  j.key("in_contact").value(s.in_contact()).key("penetration_m").value(s.penetration_m());
  j.key("stiffness_n_per_m").value(s.stiffness_n_per_m()).end_object();
}

void write_json(Json& j, const MarkerPose& s) {
  j.begin_object();
  write_str(j, "camera", s.camera());
  j.key("tag_id").value(s.tag_id());
  write_str(j, "family", s.family());
  j.key("stamp");
  write_json(j, s.stamp());
  j.key("frame").value(s.frame()).key("tag_in_camera");
  write_json(j, s.tag_in_camera());
  j.key("tag_size_m").value(s.tag_size_m());
  j.key("reprojection_error_px").value(s.reprojection_error_px());
  j.key("decision_margin").value(s.decision_margin()).key("latency_ms").value(s.latency_ms());
  j.end_object();
}

void write_json(Json& j, const CameraFrame& s) {
  j.begin_object();
  write_str(j, "camera", s.camera());
  j.key("stamp");
  write_json(j, s.stamp());
  j.key("frame").value(s.frame()).key("width").value(s.width()).key("height").value(s.height());
  write_str(j, "encoding", s.encoding());
  j.key("fx").value(s.fx()).key("fy").value(s.fy()).key("cx").value(s.cx()).key("cy").value(s.cy());
  j.key("distortion");
  write_seq(j, s.distortion());
  j.key("data_bytes").value(static_cast<std::uint64_t>(s.data().size())).end_object();
}

void write_json(Json& j, const RigidBodyState& s) {
  j.begin_object();
  write_str(j, "body", s.body());
  j.key("stamp");
  write_json(j, s.stamp());
  write_str(j, "shape", s.shape());
  write_str(j, "backend", s.backend());
  j.key("pose");
  write_json(j, s.pose());
  j.key("linear_velocity");
  write_json(j, s.linear_velocity());
  j.key("angular_velocity");
  write_json(j, s.angular_velocity());
  j.key("sleeping").value(s.sleeping()).end_object();
}

void write_json(Json& j, const RigidDivergence& s) {
  j.begin_object();
  write_str(j, "body", s.body());
  j.key("stamp");
  write_json(j, s.stamp());
  j.key("position_m").value(s.position_m()).key("orientation_rad").value(s.orientation_rad());
  j.key("velocity_m_s")
      .value(s.velocity_m_s())
      .key("angular_velocity_rad_s")
      .value(s.angular_velocity_rad_s())
      .end_object();
}

void write_json(Json& j, const DeformedMesh& s) {
  j.begin_object();
  write_str(j, "mesh", s.mesh());
  j.key("stamp");
  write_json(j, s.stamp());
  j.key("topology_version").value(s.topology_version()).key("positions");
  write_seq(j, s.positions());
  j.key("normals");
  write_seq(j, s.normals());
  j.end_object();
}

void write_json(Json& j, const MeshTopology& s) {
  j.begin_object();
  write_str(j, "mesh", s.mesh());
  j.key("topology_version").value(s.topology_version());
  j.key("vertex_count").value(s.vertex_count()).key("triangles");
  write_seq(j, s.triangles());
  j.end_object();
}

void write_json(Json& j, const ServiceStatus& s) {
  j.begin_object();
  write_str(j, "service", s.service());
  j.key("stamp");
  write_json(j, s.stamp());
  j.key("pid").value(s.pid());
  write_str(j, "mode", s.mode());
  write_str(j, "state", s.state());
  j.key("rate_target_hz").value(s.rate_target_hz());
  j.key("rate_achieved_hz").value(s.rate_achieved_hz());
  j.key("jitter_p50_us").value(s.jitter_p50_us()).key("jitter_p99_us").value(s.jitter_p99_us());
  j.key("step_p99_us").value(s.step_p99_us()).key("steps").value(s.steps());
  j.key("overruns").value(s.overruns()).key("samples_rejected").value(s.samples_rejected());
  write_str(j, "last_rejection", s.last_rejection());
  j.key("outputs_skipped").value(s.outputs_skipped()).end_object();
}

void write_json(Json& j, const ClockTick& s) {
  j.begin_object().key("step").value(s.step()).key("sim_time_ns").value(s.sim_time_ns());
  j.key("step_ns").value(s.step_ns()).key("last").value(s.last()).end_object();
}

void write_json(Json& j, const StepDone& s) {
  j.begin_object();
  write_str(j, "service", s.service());
  j.key("step").value(s.step()).end_object();
}

}  // namespace hcosim::adapters

// hcosim_test_probe: a service for the integration tests only. Its roles
// produce and answer samples the way real services will, so the runtime,
// the launcher and the transport are tested across real processes.
//   source : publishes HapticState (HIP on a vertical sine, seq counting
//            the samples sent), counts answers; param nan_every N makes
//            every Nth sample NaN, profile P sets the writer's QoS profile.
//   wall   : answers each HapticState with the ForceFeedback of a wall at z = 0
//            and its local model; nan_every N makes every Nth answer's force
//            NaN, delay S holds each answer S seconds (to the tick).
//   camera : publishes 640x480 bgr8 CameraFrames (921,600 bytes of pixels).
//   mesh   : publishes a DeformedMesh of `vertices` vertices and its topology.
// fail_after S makes any role exit with status 3 after S seconds;
// start_delay S makes it wait S seconds before its loop, as a service
// building its model does; stop_delay S, after it, as a stop that hangs.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <thread>

#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

struct Probe {
  Service& svc;
  std::string name;
  double nan_every, fail_after, stiffness;
  std::uint32_t vertices;
  std::int64_t start = mono_ns();
  std::uint64_t steps = 0, sent = 0, answers = 0;

  // Common to every role: count the step, fail on request.
  void begin_step() {
    ++steps;
    if (fail_after > 0 && (mono_ns() - start) * 1e-9 > fail_after) std::exit(3);
  }

  int source(const std::string& profile) {
    Writer<HapticState> out(svc.participant(), profile);
    Reader<ForceFeedback> in = svc.reader<ForceFeedback>();
    return svc.run([&](const Tick& tick) {
      begin_step();
      HapticState s;
      s.device("probe");
      s.seq(sent);
      s.stamp(svc.stamp(tick));
      s.orientation().w(1.0);
      s.position().z(0.01 * std::sin(2 * M_PI * tick.sim_time_ns * 1e-9));
      if (nan_every > 0 && steps % std::uint64_t(nan_every) == 0) s.position().x(std::nan(""));
      // A refused write leaves a gap in seq that no reader could fill.
      if (!out.write(s)) {
        std::printf("probe %s: Fast DDS refused sample %llu\n", name.c_str(), static_cast<unsigned long long>(sent));
        std::fflush(stdout);
      }
      ++sent;
      in.take([&](const ForceFeedback&) { ++answers; });
    });
  }

  // The wall at z = 0 answers each state `delay` s after it arrived (to
  // the tick), with its local model: exact, since the wall is linear. Out
  // of contact the model is expanded about the HIP's foot on the wall,
  // where its force is zero, so that a device rendering it late still
  // feels the wall begin at z = 0.
  int wall(double delay) {
    Reader<HapticState> in = svc.reader<HapticState>();
    Writer<ForceFeedback> out(svc.participant());
    std::deque<std::pair<std::int64_t, ForceFeedback>> due;
    return svc.run([&](const Tick& tick) {
      begin_step();
      in.take([&](const HapticState& s) {
        ForceFeedback f;
        f.source(name);
        f.device(s.device());
        f.answers_seq(s.seq());
        f.stamp(svc.stamp(tick));
        const double depth = std::max(0.0, -s.position().z());
        f.force().z(stiffness * depth);
        if (nan_every > 0 && ++sent % std::uint64_t(nan_every) == 0) f.force().y(std::nan(""));
        f.in_contact(depth > 0);
        f.penetration_m(depth);
        f.stiffness_n_per_m(stiffness);
        f.position(s.position());
        if (depth == 0) f.position().z(0);
        f.jacobian()[8] = -stiffness;
        f.normal().z(1);
        f.valid_radius_m(0.005);
        due.emplace_back(mono_ns() + std::int64_t(delay * 1e9), f);
      });
      while (!due.empty() && due.front().first <= mono_ns()) {
        out.write(due.front().second);
        due.pop_front();
      }
    });
  }

  int camera() {
    Writer<CameraFrame> out(svc.participant());
    return svc.run([&](const Tick& tick) {
      begin_step();
      CameraFrame f;
      f.camera(name);
      f.stamp(svc.stamp(tick));
      f.frame(steps - 1);
      f.width(640);
      f.height(480);
      f.encoding("bgr8");
      f.fx(600), f.fy(600), f.cx(320), f.cy(240);
      f.data().assign(640 * 480 * 3, std::uint8_t(steps));
      out.write(f);
      ++sent;
    });
  }

  int mesh() {
    Writer<DeformedMesh> out(svc.participant());
    Writer<MeshTopology> topology(svc.participant());
    MeshTopology t;
    t.mesh(name);
    t.topology_version(1);
    t.vertex_count(vertices);
    for (std::uint32_t i = 0; i + 2 < vertices; ++i) t.triangles().insert(t.triangles().end(), {i, i + 1, i + 2});
    topology.write(t);
    return svc.run([&](const Tick& tick) {
      begin_step();
      if (out.matched() == 0) return svc.skip_output();
      DeformedMesh m;
      m.mesh(name);
      m.stamp(svc.stamp(tick));
      m.topology_version(1);
      m.positions().resize(3 * vertices);
      // Vertex i sits at (i, step, -i) mm (mod 1000), so a reader can check every value.
      for (std::uint32_t i = 0; i < vertices; ++i) {
        m.positions()[3 * i] = 1e-3f * float(i % 1000);
        m.positions()[3 * i + 1] = 1e-3f * float(tick.step % 1000);
        m.positions()[3 * i + 2] = -1e-3f * float(i % 1000);
      }
      out.write(m);
      ++sent;
    });
  }
};

int run(Options o) {
  Service svc(o);
  const adapters::Config& p = svc.params();
  p.allow_only(
      {"role", "nan_every", "fail_after", "vertices", "stiffness", "profile", "start_delay", "delay", "stop_delay"});
  const std::string role = p.text("role", "source", {"source", "wall", "camera", "mesh"});
  std::this_thread::sleep_for(std::chrono::duration<double>(p.number("start_delay", 0, 0, 60)));
  Probe probe{svc,
              o.name,
              p.number("nan_every", 0, 0, 1e6),
              p.number("fail_after", 0, 0, 1e6),
              p.number("stiffness", 500, 0, 1e5),
              std::uint32_t(p.number("vertices", 1000, 3, 1e6))};
  const int code = role == "source"   ? probe.source(p.text("profile", "control", {"control", "state"}))
                   : role == "wall"   ? probe.wall(p.number("delay", 0, 0, 1))
                   : role == "camera" ? probe.camera()
                                      : probe.mesh();
  std::printf("probe %s: role %s, steps %llu, sent %llu, answers %llu\n", o.name.c_str(), role.c_str(),
              static_cast<unsigned long long>(probe.steps), static_cast<unsigned long long>(probe.sent),
              static_cast<unsigned long long>(probe.answers));
  std::this_thread::sleep_for(std::chrono::duration<double>(p.number("stop_delay", 0, 0, 60)));
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_test_probe", "a service for the integration tests only", argc, argv, run);
}

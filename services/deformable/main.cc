// hcosim_deformable: the deformable object service (seed 001's hybrid
// model, seed 000's elastic sheet and semi-sphere). Every servo tick it
// takes the latest HapticState of its device, touches each object and
// answers with one ForceFeedback per object; hybrid objects advance their
// behavior model at its own rate; at the visual rate a worker thread maps
// and publishes each object's DeformedMesh, unless no reader is matched.
// Topologies are written once, latched for late joiners. Params:
// docs/deformable.md.
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "deformable/elastic_surface.h"
#include "deformable/hybrid.h"
#include "deformable/map_cache.h"
#include "deformable/mesh_idl.h"
#include "device/haptic_idl.h"
#include "service.h"

using namespace hcosim;
using namespace hcosim::rt;

namespace {

struct Item {
  std::string name;
  std::unique_ptr<deformable::Object> model;
  double behavior_time = 0;  // s, simulated time the behavior model reached
  std::uint64_t contacts = 0;  // ticks in contact
  double max_force = 0;        // N
  std::uint64_t frames = 0;    // meshes published
};

// `cache`: the folder that keeps hybrid objects' visual maps between runs.
std::unique_ptr<deformable::Object> make_object(const Params& o, const std::string& name, double servo_dt,
                                                const std::string& cache) {
  const std::string model = o.text("model", "hybrid", {"hybrid", "sheet", "semisphere"});
  const auto c = o.vec3("centre", {0, 0, model == "hybrid" ? 0.05 : 0});
  if (model == "hybrid") {
    o.allow_only({"name", "model", "centre", "size", "elements", "stiff_ratio", "map", "keep", "behavior_rate",
                  "visual_subdivisions", "rounding"});
    deformable::HybridSpec s;
    s.centre = {c[0], c[1], c[2]};
    s.size = o.number("size", s.size, 0.01, 2);
    s.elements = o.whole("elements", s.elements, 3, 100);
    s.stiff_ratio = o.number("stiff_ratio", s.stiff_ratio, 1, 100);
    s.map = deformable::parse_visual_map(o.text("map", "mvc_sparse", {"mvc", "mvc_sparse", "trilinear"}));
    s.keep = o.number("keep", s.keep, 0.5, 1);
    s.behavior.dt = 1 / o.number("behavior_rate", 1000, 10, 10000);
    s.visual_subdivisions = o.whole("visual_subdivisions", s.visual_subdivisions, 1, 300);
    s.visual_exponent = o.number("rounding", s.visual_exponent, 2, 64);
    std::printf("%s: hybrid, %d^3 chains and masses, %d visual vertices by %s; building the map (kept in %s)\n",
                name.c_str(), s.elements, 6 * s.visual_subdivisions * s.visual_subdivisions + 2, deformable::name(s.map),
                cache.c_str());
    std::fflush(stdout);
    return std::make_unique<deformable::Hybrid>(s, deformable::map_cache(cache, s));
  }
  o.allow_only({"name", "model", "centre", "size", "resolution", "stiffness", "damping", "prestretch"});
  deformable::SurfaceSpec s;
  s.shape = model == "sheet" ? deformable::Shape::sheet : deformable::Shape::semisphere;
  s.centre = {c[0], c[1], c[2]};
  s.size = o.number("size", s.size, 0.01, 2);
  s.resolution = o.whole("resolution", s.resolution, 3, 200);
  s.material.k = o.number("stiffness", s.material.k, 1e-3, 1e5);
  s.material.b = o.number("damping", s.material.b, 0, 1e3);
  s.prestretch = o.number("prestretch", s.prestretch, 0, 0.4);
  s.options.dt = servo_dt;
  return std::make_unique<deformable::ElasticSurface>(s);
}

// One visual frame (every object's mesh) at a time on its own thread, so
// that mapping a dense mesh never delays a servo tick. A frame that finds
// the worker busy is dropped and counted.
class VisualWorker {
 public:
  VisualWorker(Writer<DeformedMesh>& out, std::vector<Item>& items) : out_(out), items_(items), thread_([this] { loop(); }) {}
  ~VisualWorker() { stop(); }
  // Publishes the frame in progress, then ends the thread.
  void stop() {
    {
      std::lock_guard<std::mutex> l(m_);
      stop_ = true;
    }
    cv_.notify_one();
    if (thread_.joinable()) thread_.join();
  }
  // Each item's cage, in order; false if the previous frame is still being
  // published. With `wait` (lockstep, where every frame must go out) it
  // waits for that frame instead.
  bool post(std::vector<Eigen::Matrix3Xd> cages, const StepStamp& stamp, bool wait) {
    std::unique_lock<std::mutex> l(m_);
    if (wait) cv_.wait(l, [this] { return !busy_; });
    if (busy_) return false;
    busy_ = true, cages_ = std::move(cages), stamp_ = stamp;
    cv_.notify_one();
    return true;
  }
  Window& frame_ms() { return frame_ms_; }

 private:
  void loop() {
    std::unique_lock<std::mutex> l(m_);
    for (;;) {
      cv_.wait(l, [this] { return stop_ || busy_; });
      if (busy_) {
        l.unlock();
        const std::int64_t t0 = mono_ns();
        for (std::size_t k = 0; k < items_.size(); ++k) {
          Item& it = items_[k];
          deformable::fill_mesh(sample_, it.name, stamp_, it.model->surface_from(cages_[k]), it.model->triangles());
          out_.write(sample_);
          ++it.frames;
        }
        l.lock();
        frame_ms_.add((mono_ns() - t0) * 1e-6);
        busy_ = false;
        cv_.notify_all();  // a waiting post()
      }
      if (stop_) return;
    }
  }

  Writer<DeformedMesh>& out_;
  std::vector<Item>& items_;
  std::mutex m_;
  std::condition_variable cv_;
  bool busy_ = false, stop_ = false;
  std::vector<Eigen::Matrix3Xd> cages_;
  StepStamp stamp_;
  DeformedMesh sample_;
  Window frame_ms_{1 << 12};
  std::thread thread_;  // last: starts once the rest is built
};

int run(int argc, char** argv) {
  Service svc(parse_options(argc, argv));
  const Params& p = svc.params();
  p.allow_only({"device", "visual_rate", "objects"});
  const std::string device = p.string("device", "omni");
  const double servo_dt = 1 / svc.options().rate_hz;
  const double visual_period = 1 / p.number("visual_rate", 30, 1, 240);
  std::vector<Item> items;
  for (const Params& o : p.list("objects")) {
    const std::string name = o.string("name", "");
    if (name.empty() || name.size() > 31) o.fail("name", "each object needs a name of 1 to 31 characters");
    for (const Item& it : items)
      if (it.name == name) o.fail("name", "two objects are named '" + name + "'");
    items.push_back({name, make_object(o, name, servo_dt, svc.options().out + "/cache")});
  }
  if (items.empty()) p.fail("objects", "hcosim_deformable: params.objects lists no object; docs/deformable.md");

  Reader<HapticState> in = svc.reader<HapticState>();
  Writer<ForceFeedback> force(svc.participant());
  Writer<DeformedMesh> meshes(svc.participant());
  Writer<MeshTopology> topology(svc.participant());
  for (Item& it : items) {
    MeshTopology t = deformable::mesh_topology(it.name, int(it.model->surface().cols()), it.model->triangles());
    topology.write(t);
  }
  VisualWorker visual(meshes, items);
  Window tick_us(1 << 16), behavior_us(1 << 16);
  HapticState latest;
  bool have = false;
  std::uint64_t frames_dropped = 0;
  double next_frame = 0;
  const int status = svc.run([&](const Tick& tick) {
    const double now = tick.sim_time_ns * 1e-9;
    svc.take(in, tick, [&](const HapticState& s) {
      if (s.device().to_string() == device) latest = s, have = true;
    });
    const std::int64_t t0 = mono_ns();
    if (have) {
      const Eigen::Vector3d hip = device::from_idl(latest.position());
      const bool grab = latest.buttons() & 1u;
      for (Item& it : items) {
        const deformable::Touch t = it.model->touch(servo_dt, hip, grab);
        it.contacts += t.in_contact;
        it.max_force = std::max(it.max_force, t.force.norm());
        ForceFeedback f = device::force_feedback(it.name, device, latest.seq(), svc.stamp(tick),
                                                 {t.force, t.in_contact, t.depth, t.stiffness});
        force.write(f);
      }
    }
    if (have) tick_us.add((mono_ns() - t0) * 1e-3);
    // After the answers are out, so that behavior steps never delay a force.
    const std::int64_t t1 = mono_ns();
    bool stepped = false;
    for (Item& it : items) {
      const double dt = it.model->behavior_dt();
      for (; dt > 0 && it.behavior_time + 0.5 * dt <= now + servo_dt; it.behavior_time += dt) it.model->advance(), stepped = true;
    }
    if (stepped) behavior_us.add((mono_ns() - t1) * 1e-3);
    if (now + 1e-12 >= next_frame) {
      next_frame += visual_period;
      if (meshes.matched() == 0) {
        for (std::size_t k = 0; k < items.size(); ++k) svc.skip_output();
      } else {
        std::vector<Eigen::Matrix3Xd> cages;
        for (const Item& it : items) cages.push_back(it.model->cage());
        if (!visual.post(std::move(cages), svc.stamp(tick), svc.options().mode == Mode::kLockstep)) ++frames_dropped;
      }
    }
  });
  visual.stop();
  for (const Item& it : items)
    std::printf("%s: %llu ticks in contact, max force %.3f N, %llu meshes published\n", it.name.c_str(),
                static_cast<unsigned long long>(it.contacts), it.max_force, static_cast<unsigned long long>(it.frames));
  std::printf("%s: haptic answer p50 %.1f us p99 %.1f us over %zu ticks; behavior p50 %.1f us p99 %.1f us; "
              "visual frame (all objects) p50 %.2f ms p99 %.2f ms, %llu dropped (worker busy)\n",
              svc.options().name.c_str(), tick_us.percentile(0.5), tick_us.percentile(0.99), tick_us.size(),
              behavior_us.percentile(0.5), behavior_us.percentile(0.99),
              visual.frame_ms().percentile(0.5), visual.frame_ms().percentile(0.99),
              static_cast<unsigned long long>(frames_dropped));
  return status;
}

}  // namespace

int main(int argc, char** argv) { return guarded_main("hcosim_deformable", [&] { return run(argc, argv); }); }

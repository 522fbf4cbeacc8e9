// hcosim_deformable: the deformable object service (seed 001's hybrid
// model, seed 000's elastic sheet and semi-sphere). In real time a haptic
// thread answers each HapticState of its device as it arrives: it touches
// each object and writes one ForceFeedback per object, with the local
// model the device renders if a later answer is late. The loop, at normal
// priority, advances hybrid objects' behavior models at their own rate; at
// the visual rate a worker thread maps and publishes each object's
// DeformedMesh, unless no reader is matched. In lockstep the step answers
// the device's state of the same step, then advances.
// Topologies are written once, latched for late joiners. adapters::Config:
// docs/deformable.md.
#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "adapters/deformable/deformable_config.h"
#include "adapters/deformable/mesh_idl.h"
#include "adapters/device/haptic_idl.h"
#include "models/deformable/hybrid.h"
#include "services/runtime/haptic_answer.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

struct Item {
  std::string name;
  std::unique_ptr<models::deformable::Object> model;
  double behavior_time = 0;     // s, simulated time the behavior model reached
  std::uint64_t contacts = 0;   // ticks in contact
  double max_force = 0;         // N
  std::uint64_t frames = 0;     // meshes published
  adapters::device::Feel said;  // the last answer written (haptic thread)
  std::uint64_t said_seq = 0;   // the state it answered
};

// Kept from an object's reach by a free-space answer: the reach is exact
// (models::deformable::Object::reach), so only rounding, and a HIP that moves on
// while its answer is computed, are covered.
constexpr double kFreeMarginM = 0.001;

// How far the HIP may go with nothing of the object near.
double free_clearance(const models::deformable::Object& o, const Eigen::Vector3d& hip) {
  return o.reach().exteriorDistance(hip) - kFreeMarginM;
}

// What the device feels from one object's touch, with the local model it
// renders until the next answer: stiffness along the face's normal (in a
// grab the object pulls, so no one-sided test).
adapters::device::Feel feel(const models::deformable::Touch& t, const Eigen::Vector3d& hip, bool grab,
                            double clearance) {
  if (!t.in_contact) return adapters::device::free_feel(hip, clearance);
  adapters::device::Feel f = adapters::device::contact_feel(t.force, hip, t.normal, t.stiffness, t.depth,
                                                            adapters::device::kContactModelRadius);
  if (grab) f.normal.setZero();
  return f;
}

// One visual frame (every object's mesh) at a time on its own thread, so
// that mapping a dense mesh never delays a servo tick. A frame that finds
// the worker busy is dropped and counted as shed (ServiceStatus).
class VisualWorker {
 public:
  VisualWorker(Service& svc, Writer<DeformedMesh>& out, std::vector<Item>& items)
      : svc_(svc), out_(out), items_(items), thread_([this] { loop(); }) {}
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
    if (busy_) {
      svc_.shed_output();
      return false;
    }
    busy_ = true, cages_ = std::move(cages), stamp_ = stamp;
    cv_.notify_one();
    return true;
  }
  Window& frame_ms() { return frame_ms_; }
  // Frames dropped because the paced link still carried the last one.
  std::uint64_t link_shed() const { return link_shed_; }

 private:
  void loop() {
    lower_to_normal();  // meshes go after every haptic-rate thread (the camera's and view's peers)
    std::unique_lock<std::mutex> l(m_);
    for (;;) {
      cv_.wait(l, [this] { return stop_ || busy_; });
      if (busy_) {
        l.unlock();
        const std::int64_t t0 = mono_ns();
        // Paced (network bulk_mbit): a link still carrying the last frame
        // drops this one, counted, rather than queueing it behind.
        const bool shed = out_.paced() && !out_.caught_up();
        if (shed) svc_.shed_output(), ++link_shed_;
        for (std::size_t k = 0; k < items_.size() && !shed; ++k) {
          Item& it = items_[k];
          adapters::deformable::fill_mesh(sample_, it.name, stamp_, it.model->surface_from(cages_[k]),
                                          it.model->triangles());
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

  Service& svc_;
  Writer<DeformedMesh>& out_;
  std::vector<Item>& items_;
  std::mutex m_;
  std::condition_variable cv_;
  bool busy_ = false, stop_ = false;
  std::atomic<std::uint64_t> link_shed_{0};
  std::vector<Eigen::Matrix3Xd> cages_;
  StepStamp stamp_;
  DeformedMesh sample_;
  Window frame_ms_{1 << 12};
  std::thread thread_;  // last: starts once the rest is built
};

int run(const Options& options) {
  Service svc(options);
  const double servo_dt = 1 / svc.options().rate_hz;
  const adapters::deformable::DeformableConfig config = adapters::deformable::deformable_config(svc.params(), servo_dt);
  const std::string& device = config.device;
  const double visual_period = 1 / config.visual_rate_hz;
  // HCOSIM_CACHE lets several runs share one folder of maps and gains
  // (the integration tests do); writes are whole files, renamed into place.
  const char* shared = std::getenv("HCOSIM_CACHE");
  const std::string cache = shared && *shared ? shared : svc.options().out + "/cache";
  std::vector<Item> items;
  for (const adapters::deformable::ObjectConfig& o : config.objects) {
    if (o.model == "hybrid") {
      const models::deformable::HybridSpec& s = o.hybrid;
      if (s.shape.triangles.empty())
        std::printf("%s: hybrid, %d^3 chains and masses, %d visual vertices by %s; building the map (kept in %s)\n",
                    o.name.c_str(), s.elements, 6 * s.visual_subdivisions * s.visual_subdivisions + 2,
                    models::deformable::name(s.map), cache.c_str());
      else
        std::printf(
            "%s: hybrid from a mesh, %d nodes along its longest side, %d visual vertices by %s; building the map "
            "(kept in %s)\n",
            o.name.c_str(), s.elements, int(s.shape.vertices.cols()), models::deformable::name(s.map), cache.c_str());
      std::fflush(stdout);
    }
    Item item;
    item.name = o.name;
    const std::int64_t t0 = mono_ns();
    item.model = adapters::deformable::make_object(o, cache);
    if (o.model == "hybrid") {
      std::printf("%s: built in %.1f s\n", o.name.c_str(), (mono_ns() - t0) * 1e-9);
      std::fflush(stdout);
    }
    items.push_back(std::move(item));
  }

  Reader<HapticState> in = svc.reader<HapticState>();
  Writer<ForceFeedback> force(svc.participant());
  Writer<DeformedMesh> meshes(svc.participant());
  Writer<MeshTopology> topology(svc.participant());
  for (Item& it : items) {
    MeshTopology t =
        adapters::deformable::mesh_topology(it.name, int(it.model->surface().cols()), it.model->triangles());
    topology.write(t);
  }
  // What touch() changes is shared by the haptic thread and the loop's
  // couple() and cage(): one lock per object, held for those calls only.
  std::vector<std::unique_ptr<PiMutex>> locks;
  for (std::size_t k = 0; k < items.size(); ++k) locks.push_back(std::make_unique<PiMutex>());
  Window answer_us(1 << 16), behavior_us(1 << 16);
  // Every object's answer to one state, written as soon as it is computed.
  // In real time an object whose last answer still covers the HIP with
  // free space (adapters::device::answer_covered) is touched after the others and
  // not answered: the device renders it without waiting, and the answers
  // it waits for go out first.
  const bool realtime = svc.options().mode == adapters::Mode::kRealtime;
  std::uint64_t unanswered = 0;  // object-states left to a free-space answer
  const auto answer = [&](const HapticState& s, const StepStamp& stamp) {
    const std::int64_t t0 = mono_ns();
    const Eigen::Vector3d hip = adapters::device::from_idl(s.position());
    const bool grab = s.buttons() & 1u;
    const auto one = [&](std::size_t k, bool write) {
      Item& it = items[k];
      models::deformable::Touch t;
      double clearance;
      {
        std::lock_guard<PiMutex> l(*locks[k]);
        t = it.model->touch(servo_dt, hip, grab);
        clearance = free_clearance(*it.model, hip);
      }
      it.contacts += t.in_contact;
      it.max_force = std::max(it.max_force, t.force.norm());
      if (!write && !t.in_contact) return ++unanswered, void();
      it.said = feel(t, hip, grab, clearance);
      it.said_seq = s.seq();
      ForceFeedback f = adapters::device::force_feedback(it.name, device, s.seq(), stamp, it.said);
      force.write(f);
    };
    // Pass 0 answers the objects the device waits for, pass 1 touches the rest.
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t k = 0; k < items.size(); ++k) {
        const bool covered =
            realtime && adapters::device::answer_covered(items[k].said, items[k].said_seq, hip, s.seq(), servo_dt);
        if (covered == (pass == 1)) one(k, !covered);
      }
    answer_us.add((mono_ns() - t0) * 1e-3);
  };
  const bool group = in_haptic_group(svc, device);
  std::unique_ptr<AnswerOnArrival> haptic;
  if (svc.options().mode == adapters::Mode::kRealtime) {
    haptic = std::make_unique<AnswerOnArrival>(in, device, [&](const HapticState& s) { answer(s, answer_stamp(s)); });
    lower_below(svc.options().scheduling);  // the loop after the haptic answers; the visual worker lowers itself
  }
  VisualWorker visual(svc, meshes, items);
  HapticState latest;
  bool have = false;
  std::uint64_t frames_dropped = 0;
  double next_frame = 0;
  const int status = svc.run([&](const Tick& tick) {
    const double now = tick.sim_time_ns * 1e-9;
    if (svc.options().mode == adapters::Mode::kLockstep) {
      // In the group the device's state of this step is answered within
      // it; otherwise the latest state before it (one step behind).
      const auto keep = [&](const HapticState& s) {
        if (s.device().to_string() == device) latest = s, have = true;
      };
      if (group)
        take_state_of_step(svc, in, force, tick, device, keep);
      else
        svc.take(in, tick, keep);
      if (have) answer(latest, svc.stamp(tick));
    }
    const std::int64_t t1 = mono_ns();
    bool stepped = false;
    for (std::size_t k = 0; k < items.size(); ++k) {
      Item& it = items[k];
      const double dt = it.model->behavior_dt();
      for (; dt > 0 && it.behavior_time + 0.5 * dt <= now + servo_dt; it.behavior_time += dt) {
        {
          std::lock_guard<PiMutex> l(*locks[k]);
          it.model->couple();
        }
        it.model->integrate();
        stepped = true;
      }
    }
    if (stepped) behavior_us.add((mono_ns() - t1) * 1e-3);
    if (now + 1e-12 >= next_frame) {
      next_frame += visual_period;
      if (meshes.matched() == 0) {
        for (std::size_t k = 0; k < items.size(); ++k) svc.skip_output();
      } else {
        std::vector<Eigen::Matrix3Xd> cages;
        for (std::size_t k = 0; k < items.size(); ++k) {
          std::lock_guard<PiMutex> l(*locks[k]);
          cages.push_back(items[k].model->cage());
        }
        if (!visual.post(std::move(cages), svc.stamp(tick), svc.options().mode == adapters::Mode::kLockstep)) ++frames_dropped;
      }
    }
  });
  if (haptic) haptic->stop();
  visual.stop();
  for (const Item& it : items)
    std::printf("%s: %llu ticks in contact, max force %.3f N, %llu meshes published\n", it.name.c_str(),
                static_cast<unsigned long long>(it.contacts), it.max_force, static_cast<unsigned long long>(it.frames));
  std::printf("%s: %llu object-states left to a free-space answer\n", svc.options().name.c_str(),
              static_cast<unsigned long long>(unanswered));
  std::printf(
      "%s: haptic answer (all objects) p50 %.1f us p99 %.1f us over %zu states; "
      "behavior p50 %.1f us p99 %.1f us; "
      "visual frame (all objects) p50 %.2f ms p99 %.2f ms, %llu shed (worker busy), %llu shed (link busy, network "
      "bulk_mbit)\n",
      svc.options().name.c_str(), answer_us.percentile(0.5), answer_us.percentile(0.99), answer_us.size(),
      behavior_us.percentile(0.5), behavior_us.percentile(0.99), visual.frame_ms().percentile(0.5),
      visual.frame_ms().percentile(0.99), static_cast<unsigned long long>(frames_dropped),
      static_cast<unsigned long long>(visual.link_shed()));
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_deformable", "the deformable object service: hybrid model, elastic sheet and semi-sphere",
                      argc, argv, run);
}

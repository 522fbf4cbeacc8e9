// What the deformable object service serves, without DDS: seed 001's hybrid
// objects and seed 000's elastic sheets and semi-spheres, each touched by a
// device state and answered with one ForceFeedback and the local model the
// device renders if a later answer is late; each object's behavior model
// advanced at its own rate; each object's drawn surface for a visual
// frame. services/deformable/main.cc wires it to its topics and runs the
// visual frames on a worker thread (visual_worker.h).
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "adapters/deformable/deformable_config.h"
#include "adapters/device/haptic_idl.h"
#include "idl/mesh.h"
#include "models/deformable/object.h"
#include "services/runtime/haptic_answer.h"
#include "services/runtime/realtime.h"
#include "services/runtime/stats.h"

namespace hcosim::services::deformable {

class ObjectServer {
 public:
  // Builds every object of `config` (a hybrid's visual map and force gain
  // kept in the folder `cache`), saying on `log` what it builds and how
  // long each took. `servo_dt`: the service's step, s. In `realtime` an
  // object whose last answer still covers the HIP with free space is not
  // answered again (adapters::device::answer_covered).
  ObjectServer(const adapters::deformable::DeformableConfig& config, double servo_dt, bool realtime,
               const std::string& cache, std::FILE* log);
  ObjectServer(const ObjectServer&) = delete;
  ObjectServer& operator=(const ObjectServer&) = delete;

  // Touches every object with a device state and passes `write` each
  // answer, stamped `stamp`: those the device waits for first, then the
  // objects left to a free-space answer (touched, not answered). Safe on
  // another thread than advance() and cages().
  void answer(const HapticState& s, const StepStamp& stamp, const std::function<void(ForceFeedback&)>& write);

  // Lockstep: keeps the device's latest state and answers it at each step
  // until the next.
  void keep(const HapticState& s) { kept_ = s, have_kept_ = true; }
  void answer_kept(const StepStamp& stamp, const std::function<void(ForceFeedback&)>& write) {
    if (have_kept_) answer(kept_, stamp, write);
  }

  // Steps each object's behavior model at its own rate up to simulated
  // time `now` plus one servo step (s).
  void advance(double now);

  // Each object's cage displacements now, for a visual frame.
  std::vector<Eigen::Matrix3Xd> cages() const;
  // Object k's drawn surface from its cage displacements, as `sample`
  // (stamped `stamp`); counted as a mesh published. Reads nothing answer()
  // or advance() change.
  void mesh(std::size_t k, const Eigen::Matrix3Xd& cage, const StepStamp& stamp, DeformedMesh& sample);
  // Each object's topology, latched for late joiners.
  std::vector<MeshTopology> topologies() const;

  // What the visual frames cost and shed, for the closing line.
  struct VisualStats {
    const runtime::Window* frame_ms = nullptr;
    std::uint64_t shed_busy = 0;  // frames dropped: the worker was busy
    std::uint64_t shed_link = 0;  // frames dropped: the paced link still carried the last one
  };
  // Writes the closing lines to `out`: each object's contacts, largest
  // force and meshes published, the answers left to free space, and what
  // answering, the behavior steps and the visual frames cost.
  void report(std::FILE* out, const std::string& service, const VisualStats& visual) const;

  const std::string& device() const { return device_; }
  std::size_t size() const { return items_.size(); }
  const models::deformable::Object& object(std::size_t k) const { return *items_[k].model; }

  // m, kept from an object's reach by a free-space answer: the reach is
  // exact (models::deformable::Object::reach), so only rounding, and a HIP
  // that moves on while its answer is computed, are covered.
  static constexpr double kFreeMarginM = 0.001;

 private:
  struct Item {
    std::string name;
    std::unique_ptr<models::deformable::Object> model;
    double behavior_time = 0;     // s, simulated time the behavior model reached
    std::uint64_t contacts = 0;   // ticks in contact
    double max_force = 0;         // N
    std::uint64_t frames = 0;     // meshes published
    adapters::device::Feel said;  // the last answer written (haptic thread)
    std::uint64_t said_seq = 0;   // the state it answered
    bool covered = false;         // this state: its last answer covers the HIP (haptic thread)
    // What touch() changes is shared by the haptic thread and the loop's
    // couple() and cage(): one lock per object, held for those calls only.
    std::unique_ptr<runtime::PiMutex> lock = std::make_unique<runtime::PiMutex>();
  };

  std::string device_;
  double servo_dt_;
  bool realtime_;
  std::vector<Item> items_;
  HapticState kept_;
  bool have_kept_ = false;
  runtime::AnswerStats answers_;
  runtime::Window behavior_us_{1 << 16};
};

}  // namespace hcosim::services::deformable

// What the rigid body service serves, without DDS: Lee and Chun's cubes and
// spheres (000 §2.1), each touched through a virtual coupling to a
// god-object proxy (models/rigid/coupling.h), stepped by the analytic
// model, MuJoCo, or both side by side (crosscheck). A device state is
// answered with one ForceFeedback per body, with the local model the device
// renders if a later answer is late; the opposite of each answered force,
// held for the device's tick, is owed to its body and handed to it as a
// load at the next step. services/rigid/main.cc wires it to its topics.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "adapters/device/haptic_idl.h"
#include "adapters/rigid/rigid_config.h"
#include "idl/rigid.h"
#include "models/rigid/coupling.h"
#include "models/rigid/mujoco_world.h"
#include "models/rigid/world.h"
#include "services/runtime/haptic_answer.h"
#include "services/runtime/realtime.h"
#include "services/runtime/stats.h"

namespace hcosim::services::rigid {

class BodyServer {
 public:
  // `dt`: the service's step, s. In `realtime` a body whose last answer
  // still covers the HIP with free space is not answered again
  // (adapters::device::answer_covered): the device renders it without
  // waiting. Building the MuJoCo scene takes a moment (the service says so).
  BodyServer(const adapters::rigid::RigidConfig& config, double dt, bool realtime);
  BodyServer(const BodyServer&) = delete;
  BodyServer& operator=(const BodyServer&) = delete;

  // Touches every body with a device state and passes `write` each answer,
  // stamped `stamp`. Safe on another thread than step().
  void answer(const HapticState& s, const StepStamp& stamp, const std::function<void(ForceFeedback&)>& write);

  // Lockstep: keeps the device's latest state, which came at simulated time
  // `now` (s), and answers it at each step until the next: its velocity as
  // zero once it is older than a tick of a silent device.
  void keep(const HapticState& s, double now);
  void answer_kept(double now, const StepStamp& stamp, const std::function<void(ForceFeedback&)>& write);

  // One physics tick at simulated time `now` (s): each body's load from its
  // coupling, the scene stepped. The states due, stamped `stamp`: an awake
  // body's every tick, a sleeping one's when it falls asleep and every
  // kSleepingRepeat after (for late subscribers); in crosscheck mode each
  // with its divergence from MuJoCo.
  struct Outputs {
    std::vector<RigidBodyState> states;
    std::vector<RigidDivergence> divergences;
  };
  Outputs& step(double now, const StepStamp& stamp);

  // Writes the closing lines to `out`: each body's place and speed, the
  // answers' and the steps' costs, contacts and touches, and in crosscheck
  // mode the largest divergence from MuJoCo.
  void report(std::FILE* out, const std::string& service) const;

  const std::string& device() const { return config_.device; }
  std::size_t size() const { return items_.size(); }
  models::rigid::Body body(std::size_t i) const;

  static constexpr double kStaleState = 0.02;     // s: the longest a device state's force is held on a body
  static constexpr double kSleepingRepeat = 0.2;  // s
  static constexpr double kFreeMarginM = 0.004;   // m, kept from a body by a free-space answer
  static constexpr double kParkedTipZ = 1.0;      // m: where the seed's tip particle is kept, clear of any scene

 private:
  struct Item {
    std::string name;
    double max_speed = 0;     // m/s
    double next_publish = 0;  // s, when a sleeping body is published again
    bool was_sleeping = false;
    adapters::device::Feel feel;  // this state's
    adapters::device::Feel said;  // the last answer written
    std::uint64_t said_seq = 0;   // the state it answered
  };

  models::rigid::Body held_body(std::size_t i) const;  // from the primary model, the scene's lock held

  adapters::rigid::RigidConfig config_;
  double dt_;
  bool realtime_;
  std::unique_ptr<models::rigid::World> analytic_;
  std::unique_ptr<models::rigid::MujocoWorld> mujoco_;
  std::vector<Item> items_;
  std::vector<models::rigid::Coupling> couplings_;
  // The haptic thread touches the bodies through their couplings, the loop
  // steps them: one lock for the scene, held by each for that part only.
  mutable runtime::PiMutex scene_;
  double last_device_s_ = -1;  // the device clock of the last state answered; < 0: none yet
  HapticState kept_;
  bool have_kept_ = false;
  double kept_at_ = 0;  // s, simulated
  runtime::AnswerStats answers_;
  std::uint64_t contact_ticks_ = 0;
  double felt_ = 0;  // N, the largest force answered
  runtime::Window step_us_{1 << 16};
  std::uint64_t touches_ = 0;                // body-body impulses of the analytic model
  double worst_[4] = {0, 0, 0, 0};           // the largest divergences
  std::vector<models::rigid::Body> bodies_;  // after this tick's step (reused: no allocation per tick)
  Outputs outputs_;
};

}  // namespace hcosim::services::rigid

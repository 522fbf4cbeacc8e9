// hcosim_rigid: the rigid body service (seed 000 §2.1). In real time a
// haptic thread answers each HapticState of its device as it arrives: one
// ForceFeedback per body from its virtual coupling to a god-object proxy
// (models/rigid/coupling.h), with the local model the device renders if a
// later answer is late; the opposite of each answered force, held for the
// device's tick, is owed to its body. Every physics tick the loop hands the
// bodies what they are owed as a load, steps the scene (the analytic
// model, MuJoCo, or both side by side in crosscheck mode) and publishes
// each body's RigidBodyState; in crosscheck mode also each body's
// RigidDivergence. In lockstep the step answers the device's state of the
// same step, then steps the bodies.
// adapters::Config: docs/rigid.md.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <vector>

#include "adapters/device/haptic_idl.h"
#include "adapters/rigid/rigid_config.h"
#include "adapters/rigid/rigid_idl.h"
#include "models/haptic/local_model.h"
#include "models/rigid/coupling.h"
#include "models/rigid/mujoco_world.h"
#include "models/rigid/world.h"
#include "services/runtime/haptic_answer.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services::runtime;

namespace {

// Where the seed's tip particle (world.h) is kept: 1 m above the marker,
// clear of any scene the service accepts; the stylus touches the bodies
// through their couplings instead.
constexpr double kParkedTipZ = 1.0;
// Kept from a body by a free-space answer: gravity over the horizon
// (0.5 g t^2, 2 mm in 20 ms) and the body's speed changing meanwhile.
constexpr double kFreeMarginM = 0.004;
// The longest a device state's force is held on a body: a state after a
// longer silence (or the first) stands for one tick of the service.
constexpr double kStaleState = 0.02;  // s
// A sleeping body's state is repeated this often, for late subscribers.
constexpr double kSleepingRepeat = 0.2;  // s

struct Item {
  std::string name;
  double max_speed = 0;     // m/s
  double next_publish = 0;  // s, when a sleeping body is published again
  bool was_sleeping = false;
};

// How far the HIP may go with nothing of body `b` near for the next
// haptic::kFreeHorizonS: its distance to the body's bounding sphere, less
// the tip's radius, what the body may travel meanwhile at its current
// speed (a hit body slows; gravity adds under 2 mm in 20 ms) and a margin
// for that.
double free_clearance(const models::rigid::Body& b, double tip_radius, const Eigen::Vector3d& hip) {
  const double reach = b.shape == models::rigid::Shape::sphere ? b.size : std::sqrt(3.0) * b.size;
  const double travel = (b.v.norm() + b.w.norm() * reach) * models::haptic::kFreeHorizonS;
  return (hip - b.x).norm() - reach - tip_radius - travel - kFreeMarginM;
}

int run(const Options& options) {
  Service svc(options);
  const adapters::rigid::RigidConfig config = adapters::rigid::rigid_config(svc.params());
  const std::string& device = config.device;
  const std::string& backend = config.backend;
  const models::rigid::WorldSpec& spec = config.spec;
  const int substeps = config.mujoco_substeps;
  const std::vector<models::rigid::Body>& bodies = config.bodies;
  const double dt = 1 / svc.options().rate_hz;
  std::vector<Item> items;
  for (const std::string& name : config.names) items.push_back({name});

  // The primary model gives the states and the forces; in crosscheck mode
  // MuJoCo runs beside the analytic model and only its divergence is told.
  std::unique_ptr<models::rigid::World> analytic;
  std::unique_ptr<models::rigid::MujocoWorld> mujoco;
  if (backend != "mujoco") analytic = std::make_unique<models::rigid::World>(spec, bodies);
  if (backend != "analytic") {
    std::printf("%s: building the MuJoCo scene, %d substeps of %.3g ms per tick\n", svc.options().name.c_str(),
                substeps, 1e3 * dt / substeps);
    std::fflush(stdout);
    mujoco = std::make_unique<models::rigid::MujocoWorld>(spec, bodies, dt / substeps);
  }
  const char* primary = analytic ? "analytic" : "mujoco";
  const auto body = [&](std::size_t i) { return analytic ? analytic->bodies()[i] : mujoco->body(i); };
  models::rigid::Tip parked;
  parked.x = {0, 0, kParkedTipZ};
  if (analytic) analytic->set_tip(parked);
  if (mujoco) mujoco->set_tip(parked);

  Reader<HapticState> in = svc.reader<HapticState>();
  Writer<ForceFeedback> force(svc.participant());
  Writer<RigidBodyState> states(svc.participant());
  Writer<RigidDivergence> divergences(svc.participant());
  std::vector<models::rigid::Coupling> couplings;
  for (const models::haptic::Friction& f : config.frictions) couplings.emplace_back(config.coupling, f);
  std::vector<adapters::device::Feel> feels(items.size());
  std::vector<adapters::device::Feel> said(items.size());  // the last answer written per body
  std::vector<std::uint64_t> said_seq(items.size());       // the state it answered
  const bool realtime = svc.options().mode == adapters::Mode::kRealtime;
  std::uint64_t unanswered = 0;  // body-states left to a free-space answer
  Window answer_us(1 << 16);
  // The haptic thread touches the bodies through their couplings, the loop
  // steps them: one lock for the scene, held by each for that part only.
  PiMutex scene;
  double last_device_s = -1;  // the device clock of the last state answered; < 0: none yet
  std::uint64_t contact_ticks = 0;
  double felt = 0;
  const auto answer = [&](const HapticState& s, const StepStamp& stamp) {
    const std::int64_t t0 = mono_ns();
    const Eigen::Vector3d h = adapters::device::from_idl(s.position());
    const Eigen::Vector3d hv = adapters::device::from_idl(s.velocity());
    {
      std::lock_guard<PiMutex> l(scene);
      // How long this state's force stands: until the device's next state,
      // taken as the time since its last one (a repeated state: none).
      const double since = s.device_time_s() - last_device_s;
      const double held = last_device_s < 0 || since > kStaleState ? dt : std::max(0.0, since);
      last_device_s = s.device_time_s();
      for (std::size_t i = 0; i < items.size(); ++i) {
        adapters::device::Feel& f = feels[i];
        const models::rigid::Body b = body(i);
        const models::rigid::Touch t = couplings[i].touch(b, spec.tip_radius, h, hv, held);
        if (!t.contact) {
          f = adapters::device::free_feel(h, free_clearance(b, spec.tip_radius, h));
          continue;
        }
        // The local model: the spring along the force's direction, none
        // past max_force (the model then holds that force).
        const Eigen::Vector3d n = t.depth > 0 ? Eigen::Vector3d((t.proxy - h) / t.depth) : t.normal;
        f = adapters::device::contact_feel(t.force, h, n, t.clamped ? 0.0 : config.coupling.stiffness, t.depth,
                                           adapters::device::kContactModelRadius);
      }
    }
    // In real time a body whose last answer still covers the HIP with free
    // space is not answered (adapters::device::answer_covered): the device
    // renders it without waiting.
    bool touching = false;
    for (std::size_t i = 0; i < items.size(); ++i) {
      touching = touching || feels[i].in_contact;
      felt = std::max(felt, feels[i].force.norm());
      if (realtime && !feels[i].in_contact && adapters::device::answer_covered(said[i], said_seq[i], h, s.seq(), dt)) {
        ++unanswered;
        continue;
      }
      said[i] = feels[i], said_seq[i] = s.seq();
      ForceFeedback f = adapters::device::force_feedback(items[i].name, device, s.seq(), stamp, feels[i]);
      force.write(f);
    }
    contact_ticks += touching;
    answer_us.add((mono_ns() - t0) * 1e-3);
  };
  const bool group = in_haptic_group(svc, device);
  std::unique_ptr<AnswerOnArrival> haptic;
  if (svc.options().mode == adapters::Mode::kRealtime) {
    haptic = std::make_unique<AnswerOnArrival>(in, device, [&](const HapticState& s) { answer(s, answer_stamp(s)); });
    lower_below(svc.options().scheduling);  // the loop steps the bodies after the haptic answers
  }
  HapticState latest;
  bool have = false;
  double state_time = 0;  // s, lockstep: the simulated time `latest` arrived
  Window step_us(1 << 16);
  std::vector<models::rigid::Body> now_bodies;  // the bodies after this tick's step (reused: no allocation per tick)
  std::uint64_t touches = 0;                    // body-body impulses of the analytic model
  double worst[4] = {0, 0, 0, 0};               // max divergences
  const int status = svc.run([&](const Tick& tick) {
    const double now = tick.sim_time_ns * 1e-9;
    if (svc.options().mode == adapters::Mode::kLockstep) {
      const auto keep = [&](const HapticState& s) {
        if (s.device().to_string() == device) latest = s, have = true, state_time = now;
      };
      if (group)
        take_state_of_step(svc, in, force, tick, device, keep);
      else
        svc.take(in, tick, keep);
      if (have) {
        if (now - state_time > kStaleState) latest.velocity(Vec3{});
        answer(latest, svc.stamp(tick));
      }
    }
    const std::int64_t t0 = mono_ns();
    now_bodies.clear();
    {
      std::lock_guard<PiMutex> l(scene);
      for (std::size_t i = 0; i < items.size(); ++i) {
        const models::rigid::Wrench w = couplings[i].load(body(i), dt);
        if (analytic) analytic->set_load(i, w.force, w.torque);
        if (mujoco) mujoco->set_load(i, w.force, w.torque);
      }
      if (analytic) touches += std::uint64_t(analytic->step(dt).touches);
      if (mujoco)
        for (int k = 0; k < substeps; ++k) mujoco->step();
      for (std::size_t i = 0; i < items.size(); ++i) now_bodies.push_back(body(i));
    }
    step_us.add((mono_ns() - t0) * 1e-3);
    const StepStamp stamp = svc.stamp(tick);
    for (std::size_t i = 0; i < items.size(); ++i) {
      Item& it = items[i];
      const models::rigid::Body& b = now_bodies[i];
      it.max_speed = std::max(it.max_speed, b.v.norm());
      // Awake bodies every tick; a sleeping one when it falls asleep, then
      // once a second.
      const bool due = !b.sleeping || !it.was_sleeping || now + 1e-12 >= it.next_publish;
      it.was_sleeping = b.sleeping;
      if (!due) continue;
      if (b.sleeping) it.next_publish = now + kSleepingRepeat;
      if (states.matched() == 0) {
        svc.skip_output();
      } else {
        RigidBodyState st = adapters::rigid::body_state(it.name, stamp, b, primary);
        states.write(st);
      }
      if (analytic && mujoco) {
        RigidDivergence d;
        {
          std::lock_guard<PiMutex> l(scene);
          d = adapters::rigid::divergence(it.name, stamp, b, mujoco->body(i));
        }
        const double e[4] = {d.position_m(), d.orientation_rad(), d.velocity_m_s(), d.angular_velocity_rad_s()};
        for (int k = 0; k < 4; ++k) worst[k] = std::max(worst[k], e[k]);
        if (divergences.matched() == 0)
          svc.skip_output();
        else
          divergences.write(d);
      }
    }
  });
  if (haptic) haptic->stop();
  for (std::size_t i = 0; i < items.size(); ++i) {
    const models::rigid::Body b = body(i);
    std::printf("%s: %s at [%.4f, %.4f, %.4f] m, max speed %.3f m/s, %s\n", items[i].name.c_str(),
                models::rigid::name(b.shape), b.x.x(), b.x.y(), b.x.z(), items[i].max_speed,
                b.sleeping ? "asleep" : "awake");
  }
  std::printf("%s: %llu body-states left to a free-space answer\n", svc.options().name.c_str(),
              static_cast<unsigned long long>(unanswered));
  std::printf(
      "%s: %s backend, bodies step p50 %.1f us p99 %.1f us over %zu ticks; haptic answer (all bodies) "
      "p50 %.1f us p99 %.1f us over %zu states; %llu body-body touches, %llu states in contact, max force %.3f N\n",
      svc.options().name.c_str(), backend.c_str(), step_us.percentile(0.5), step_us.percentile(0.99), step_us.size(),
      answer_us.percentile(0.5), answer_us.percentile(0.99), answer_us.size(), static_cast<unsigned long long>(touches),
      static_cast<unsigned long long>(contact_ticks), felt);
  if (analytic && mujoco)
    std::printf(
        "%s: max divergence from MuJoCo: position %.3g m, orientation %.3g rad, velocity %.3g m/s, "
        "angular velocity %.3g rad/s\n",
        svc.options().name.c_str(), worst[0], worst[1], worst[2], worst[3]);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  return service_main("hcosim_rigid", "the rigid body service: cubes and spheres touched through a god-object proxy",
                      argc, argv, run);
}

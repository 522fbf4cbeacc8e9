#include "services/rigid/body_server.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "adapters/rigid/rigid_idl.h"
#include "models/haptic/local_model.h"

namespace hcosim::services::rigid {

namespace {

// How far the HIP may go with nothing of body `b` near for the next
// haptic::kFreeHorizonS: its distance to the body's bounding sphere, less
// the tip's radius, what the body may travel meanwhile at its current
// speed (a hit body slows; gravity adds under 2 mm in 20 ms) and a margin
// for that.
double free_clearance(const models::rigid::Body& b, double tip_radius, const Eigen::Vector3d& hip) {
  const double reach = b.shape == models::rigid::Shape::sphere ? b.size : std::sqrt(3.0) * b.size;
  const double travel = (b.v.norm() + b.w.norm() * reach) * models::haptic::kFreeHorizonS;
  return (hip - b.x).norm() - reach - tip_radius - travel - BodyServer::kFreeMarginM;
}

}  // namespace

BodyServer::BodyServer(const adapters::rigid::RigidConfig& config, double dt, bool realtime)
    : config_(config), dt_(dt), realtime_(realtime) {
  // The primary model gives the states and the forces; in crosscheck mode
  // MuJoCo runs beside the analytic model and only its divergence is told.
  if (config.backend != "mujoco") analytic_ = std::make_unique<models::rigid::World>(config.spec, config.bodies);
  if (config.backend != "analytic")
    mujoco_ = std::make_unique<models::rigid::MujocoWorld>(config.spec, config.bodies, dt / config.mujoco_substeps);
  models::rigid::Tip parked;
  parked.x = {0, 0, kParkedTipZ};
  if (analytic_) analytic_->set_tip(parked);
  if (mujoco_) mujoco_->set_tip(parked);
  for (const std::string& name : config.names) {
    Item it;
    it.name = name;
    items_.push_back(it);
  }
  for (const models::haptic::Friction& f : config.frictions) couplings_.emplace_back(config.coupling, f);
}

models::rigid::Body BodyServer::held_body(std::size_t i) const {
  return analytic_ ? analytic_->bodies()[i] : mujoco_->body(i);
}

models::rigid::Body BodyServer::body(std::size_t i) const {
  std::lock_guard<runtime::PiMutex> l(scene_);
  return held_body(i);
}

void BodyServer::answer(const HapticState& s, const StepStamp& stamp,
                        const std::function<void(ForceFeedback&)>& write) {
  const std::int64_t t0 = runtime::mono_ns();
  const Eigen::Vector3d h = adapters::device::from_idl(s.position());
  const Eigen::Vector3d hv = adapters::device::from_idl(s.velocity());
  const double tip = config_.spec.tip_radius;
  {
    std::lock_guard<runtime::PiMutex> l(scene_);
    // How long this state's force stands: until the device's next state,
    // taken as the time since its last one (a repeated state: none).
    const double since = s.device_time_s() - last_device_s_;
    const double held = last_device_s_ < 0 || since > kStaleState ? dt_ : std::max(0.0, since);
    last_device_s_ = s.device_time_s();
    for (std::size_t i = 0; i < items_.size(); ++i) {
      adapters::device::Feel& f = items_[i].feel;
      const models::rigid::Body b = held_body(i);
      const models::rigid::Touch t = couplings_[i].touch(b, tip, h, hv, held);
      if (!t.contact) {
        f = adapters::device::free_feel(h, free_clearance(b, tip, h));
        continue;
      }
      // The local model: the spring along the force's direction, none
      // past max_force (the model then holds that force).
      const Eigen::Vector3d n = t.depth > 0 ? Eigen::Vector3d((t.proxy - h) / t.depth) : t.normal;
      f = adapters::device::contact_feel(t.force, h, n, t.clamped ? 0.0 : config_.coupling.stiffness, t.depth,
                                         adapters::device::kContactModelRadius);
    }
  }
  bool touching = false;
  for (Item& it : items_) {
    touching = touching || it.feel.in_contact;
    felt_ = std::max(felt_, it.feel.force.norm());
    if (realtime_ && !it.feel.in_contact && adapters::device::answer_covered(it.said, it.said_seq, h, s.seq(), dt_)) {
      ++answers_.unanswered;
      continue;
    }
    it.said = it.feel, it.said_seq = s.seq();
    ForceFeedback f = adapters::device::force_feedback(it.name, config_.device, s.seq(), stamp, it.feel);
    write(f);
  }
  contact_ticks_ += touching;
  answers_.us.add((runtime::mono_ns() - t0) * 1e-3);
}

void BodyServer::keep(const HapticState& s, double now) { kept_ = s, have_kept_ = true, kept_at_ = now; }

void BodyServer::answer_kept(double now, const StepStamp& stamp, const std::function<void(ForceFeedback&)>& write) {
  if (!have_kept_) return;
  if (now - kept_at_ > kStaleState) kept_.velocity(Vec3{});
  answer(kept_, stamp, write);
}

BodyServer::Outputs& BodyServer::step(double now, const StepStamp& stamp) {
  const std::int64_t t0 = runtime::mono_ns();
  bodies_.clear();
  {
    std::lock_guard<runtime::PiMutex> l(scene_);
    for (std::size_t i = 0; i < items_.size(); ++i) {
      const models::rigid::Wrench w = couplings_[i].load(held_body(i), dt_);
      if (analytic_) analytic_->set_load(i, w.force, w.torque);
      if (mujoco_) mujoco_->set_load(i, w.force, w.torque);
    }
    if (analytic_) touches_ += std::uint64_t(analytic_->step(dt_).touches);
    if (mujoco_)
      for (int k = 0; k < config_.mujoco_substeps; ++k) mujoco_->step();
    for (std::size_t i = 0; i < items_.size(); ++i) bodies_.push_back(held_body(i));
  }
  step_us_.add((runtime::mono_ns() - t0) * 1e-3);
  outputs_.states.clear();
  outputs_.divergences.clear();
  const char* primary = analytic_ ? "analytic" : "mujoco";
  for (std::size_t i = 0; i < items_.size(); ++i) {
    Item& it = items_[i];
    const models::rigid::Body& b = bodies_[i];
    it.max_speed = std::max(it.max_speed, b.v.norm());
    const bool due = !b.sleeping || !it.was_sleeping || now + 1e-12 >= it.next_publish;
    it.was_sleeping = b.sleeping;
    if (!due) continue;
    if (b.sleeping) it.next_publish = now + kSleepingRepeat;
    outputs_.states.push_back(adapters::rigid::body_state(it.name, stamp, b, primary));
    if (analytic_ && mujoco_) {
      RigidDivergence d;
      {
        std::lock_guard<runtime::PiMutex> l(scene_);
        d = adapters::rigid::divergence(it.name, stamp, b, mujoco_->body(i));
      }
      const double e[4] = {d.position_m(), d.orientation_rad(), d.velocity_m_s(), d.angular_velocity_rad_s()};
      for (int k = 0; k < 4; ++k) worst_[k] = std::max(worst_[k], e[k]);
      outputs_.divergences.push_back(d);
    }
  }
  return outputs_;
}

void BodyServer::report(std::FILE* out, const std::string& service) const {
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const models::rigid::Body b = body(i);
    std::fprintf(out, "%s: %s at [%.4f, %.4f, %.4f] m, max speed %.3f m/s, %s\n", items_[i].name.c_str(),
                 models::rigid::name(b.shape), b.x.x(), b.x.y(), b.x.z(), items_[i].max_speed,
                 b.sleeping ? "asleep" : "awake");
  }
  answers_.report_unanswered(out, service, "body");
  std::fprintf(out,
               "%s: %s backend, bodies step p50 %.1f us p99 %.1f us over %zu ticks; haptic answer (all bodies) "
               "p50 %.1f us p99 %.1f us over %zu states; %llu body-body touches, %llu states in contact, max force "
               "%.3f N\n",
               service.c_str(), config_.backend.c_str(), step_us_.percentile(0.5), step_us_.percentile(0.99),
               step_us_.size(), answers_.us.percentile(0.5), answers_.us.percentile(0.99), answers_.us.size(),
               static_cast<unsigned long long>(touches_), static_cast<unsigned long long>(contact_ticks_), felt_);
  if (analytic_ && mujoco_)
    std::fprintf(out,
                 "%s: max divergence from MuJoCo: position %.3g m, orientation %.3g rad, velocity %.3g m/s, "
                 "angular velocity %.3g rad/s\n",
                 service.c_str(), worst_[0], worst_[1], worst_[2], worst_[3]);
}

}  // namespace hcosim::services::rigid

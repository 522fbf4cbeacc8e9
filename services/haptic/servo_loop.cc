#include "services/haptic/servo_loop.h"

#include <algorithm>

#include "adapters/device/haptic_idl.h"
#include "adapters/json.h"
#include "models/haptic/local_model.h"

namespace hcosim::services::haptic {

namespace {

bool has(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

bool RoundTrips::answered(std::uint64_t seq, std::int64_t t) {
  Sent& s = at_[seq % at_.size()];
  if (s.seq != seq || s.t < 0) return false;
  window_.add((t - s.t) * 1e-3);
  s.t = -1;
  return true;
}

void Rendered::put(const std::string& source, std::uint64_t seq, const Eigen::Vector3d& f) {
  auto& ring = by_source_[source];
  ring[seq % ring.size()] = {seq, f};
}

std::optional<Eigen::Vector3d> Rendered::at(const std::string& source, std::uint64_t seq) const {
  const auto it = by_source_.find(source);
  if (it == by_source_.end()) return std::nullopt;
  const Entry& e = it->second[seq % it->second.size()];
  if (e.seq != seq) return std::nullopt;
  return e.force;
}

ServoLoop::ServoLoop(const adapters::device::DeviceConfig& config, std::string name, std::vector<std::string> group,
                     bool lockstep, std::FILE* log)
    : name_(std::move(name)),
      group_(std::move(group)),
      lockstep_(lockstep),
      log_(log),
      passivity_(config.passivity),
      dt_(1 / config.spec.servo_hz),
      source_timeout_(config.source_timeout),
      pc_(dt_, config.max_damping, config.reservoir),
      sum_(config.source_timeout),
      device_(adapters::device::make_device(config)) {}

HapticState ServoLoop::begin(const runtime::Tick& tick, const StepStamp& stamp) {
  jitter_us_.add(tick.late_us);
  frame_ = device_->begin_frame();
  now_ = tick.sim_time_ns * 1e-9;
  HapticState hs = adapters::device::haptic_state(name_, seq_, stamp, frame_, applied_);
  sent_ = runtime::mono_ns();
  rtt_.sent(seq_, sent_);
  answered_.clear();
  expected_.clear();
  if (gauss_seidel()) {
    // This step's state goes out; the group answers it within the step, and
    // the force rendered now is theirs. Answers from outside the group kept
    // from the last step count now.
    for (const ForceFeedback& s : deferred_) handle(s);
    deferred_.clear();
  }
  return hs;
}

void ServoLoop::take(const ForceFeedback& s, std::uint64_t step) {
  if (s.device().to_string() != name_) return;
  if (gauss_seidel() && s.stamp().step() == step && !has(group_, s.source().to_string()))
    deferred_.push_back(s);
  else
    handle(s);
}

void ServoLoop::handle(const ForceFeedback& s) {
  const std::string from = s.source().to_string();
  const models::haptic::LocalModel model = adapters::device::local_model(s);
  // The round trip and the rendered-force error are those of answers the
  // device waits for: a free-space one is rendered without waiting,
  // whenever it comes, and is exact.
  const bool free = models::haptic::covers(model, model.position);
  if (!free) rtt_.answered(s.answers_seq(), runtime::mono_ns());
  if (s.answers_seq() == seq_) {
    if (!has(answered_, from)) answered_.push_back(from);
  }
  // A late answer: what the user felt in its place, against it.
  else if (const auto r = rendered_.at(from, s.answers_seq()); r && !free)
    error_n_.add((adapters::device::from_idl(s.force()) - *r).norm());
  auto [it, fresh] = newest_.try_emplace(from, s.answers_seq());
  if (!fresh && s.answers_seq() < it->second) return;  // an older answer overtaken by a newer one
  it->second = s.answers_seq();
  sum_.set(from, model, now_);
}

void ServoLoop::expect() {
  sum_.expire(now_);
  for (const auto& [from, last] : newest_) {
    if (!sum_.has(from)) continue;
    if (double(seq_ - last) * dt_ <= models::haptic::kFreeHorizonS && sum_.covers(from, frame_.position))
      ++covered_;
    else
      expected_.push_back(from);
  }
}

bool ServoLoop::all_in(const std::vector<std::string>& want) const {
  return std::all_of(want.begin(), want.end(), [&](const std::string& x) { return has(answered_, x); });
}

bool ServoLoop::waiting() const { return !all_in(gauss_seidel() ? group_ : expected_); }

void ServoLoop::end() {
  const Eigen::Vector3d env = sum_.total(now_, frame_.position);
  for (const auto& [from, last] : newest_) {
    // A source that falls silent (its host gone) drops out with its force,
    // which is zero, not its last; said when it does and when it is back.
    const bool live = sum_.has(from);
    const auto silent = silent_since_.find(from);
    if (!live && silent == silent_since_.end()) {
      silent_since_.emplace(from, runtime::wall_ns());
      std::fprintf(log_,
                   "%s: source '%s' fell silent (no answer for %.3g s): its force is zero until it answers again\n",
                   name_.c_str(), from.c_str(), source_timeout_);
      std::fflush(log_);
    } else if (live && silent != silent_since_.end()) {
      std::fprintf(log_, "%s: source '%s' answers again after %.2f s silent (wall time %.3f s)\n", name_.c_str(),
                   from.c_str(), (runtime::wall_ns() - silent->second) * 1e-9, runtime::wall_ns() * 1e-9);
      std::fflush(log_);
      silent_since_.erase(silent);
    }
    if (!live) continue;
    rendered_.put(from, seq_, sum_.force_of(from));
    if (last != seq_ && (gauss_seidel() || has(expected_, from))) ++modelled_;
  }
  const std::vector<std::string>& waited = gauss_seidel() ? group_ : expected_;
  if (!waited.empty()) ++with_sources_, in_tick_ += all_in(waited);
  peak_ = std::max(peak_, env.norm());
  applied_ = device_->end_frame(passivity_ ? pc_.filter(env, frame_.velocity, applied_) : env);
  ++seq_;
}

std::string ServoLoop::report_json() const {
  // Percentiles of no sample are NaN (no late answer: no error), which
  // JSON writes as null.
  const runtime::Window& w = rtt_.window();
  adapters::Json j;
  j["ticks"] = std::uint64_t(seq_);
  j["answered"] = std::uint64_t(w.size());
  j["p50_us"] = w.percentile(0.5);
  j["p99_us"] = w.percentile(0.99);
  j["on_time_ratio"] = in_tick_ratio();
  j["jitter_p50_us"] = jitter_us_.percentile(0.5);
  j["jitter_p99_us"] = jitter_us_.percentile(0.99);
  j["modelled"] = std::uint64_t(modelled_);
  j["covered"] = std::uint64_t(covered_);
  j["late_answers"] = std::uint64_t(error_n_.size());
  j["force_error_p99_n"] = error_n_.percentile(0.99);
  j["peak_force_n"] = peak_;
  j["saturated"] = std::uint64_t(device_->saturated());
  return adapters::json_line(j);
}

void ServoLoop::report(std::FILE* out) const {
  const runtime::Window& w = rtt_.window();
  std::fprintf(out,
               "%s: %llu ticks, %zu answered, round trip p50 %.0f us p99 %.0f us, %.4f on time, %llu saturated, "
               "%llu sources timed out, %.3g J dissipated by the passivity controller\n",
               name_.c_str(), static_cast<unsigned long long>(device_->frames()), w.size(), w.percentile(0.5),
               w.percentile(0.99), in_tick_ratio(), static_cast<unsigned long long>(device_->saturated()),
               static_cast<unsigned long long>(sum_.expired()), pc_.dissipated());
  std::fprintf(out,
               "%s: wake-up jitter p50 %.0f us p99 %.0f us; %llu source-ticks rendered from a local model, "
               "%llu from a free-space one (nothing near); %zu late answers, rendered-force error p99 %.4f N of a "
               "%.3f N peak\n",
               name_.c_str(), jitter_us_.percentile(0.5), jitter_us_.percentile(0.99),
               static_cast<unsigned long long>(modelled_), static_cast<unsigned long long>(covered_), error_n_.size(),
               error_n_.percentile(0.99), peak_);
}

}  // namespace hcosim::services::haptic

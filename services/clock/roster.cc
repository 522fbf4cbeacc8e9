#include "services/clock/roster.h"

#include <sstream>
#include <utility>

namespace hcosim::services::clock {

std::string names(const std::set<std::string>& s) {
  std::string out;
  for (const auto& n : s) out += (out.empty() ? "" : ", ") + n;
  return out;
}

Roster::Roster(std::set<std::string> followers, std::int64_t now_ns)
    : followers_(std::move(followers)), join_start_ns_(now_ns) {}

void Roster::status(const std::string& service, bool starting) {
  if (!followers_.count(service)) return;
  if (starting)
    starting_.insert(service);
  else
    starting_.erase(service);
}

std::string Roster::join_failure(std::int64_t now_ns, int joined, const std::set<std::string>& deaf) const {
  const double limit = starting_.empty() ? kJoinTimeoutS : kStartTimeoutS;
  if (now_ns - join_start_ns_ <= std::int64_t(limit * 1e9)) return "";
  std::ostringstream out;
  out << "after " << limit << " s only " << joined << " of " << followers_.size() << " followers joined ("
      << names(followers_) << ")" << (deaf.empty() ? "" : "; not yet reading ticks: " + names(deaf))
      << (starting_.empty() ? "" : "; still starting: " + names(starting_));
  return out.str();
}

void Roster::tick(std::uint64_t step, std::int64_t now_ns) {
  step_ = step;
  step_start_ns_ = now_ns;
  waiting_ = followers_;
}

void Roster::done(std::uint64_t step, const std::string& service) {
  if (step == step_) waiting_.erase(service);
}

std::string Roster::step_failure(std::int64_t now_ns) const {
  if (complete() || now_ns - step_start_ns_ <= std::int64_t(kStepTimeoutS * 1e9)) return "";
  std::ostringstream out;
  out << "step " << step_ << ": no StepDone from " << names(waiting_) << " after " << kStepTimeoutS << " s";
  return out.str();
}

}  // namespace hcosim::services::clock

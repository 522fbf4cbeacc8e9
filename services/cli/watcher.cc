#include "services/cli/watcher.h"

#include <cstdio>
#include <utility>

namespace hcosim::services::cli {
namespace {

template <class... A>
std::string text(const char* f, A... a) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a...);
  return buf;
}

// "a, b, c" of the names not in `have`.
template <class Has>
std::string missing(const std::vector<std::string>& names, Has has) {
  std::string out;
  for (const auto& n : names)
    if (!has(n)) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

Watcher::Watcher(std::vector<std::string> names, int domain, bool tty)
    : names_(std::move(names)), domain_(domain), tty_(tty) {}

void Watcher::joined(const std::string& participant, const std::string& where) {
  std::lock_guard<std::mutex> l(joined_mutex_);
  joined_[participant] = where;
}

void Watcher::status(const ServiceStatus& s) {
  ServiceStatus& last = latest_[s.service().to_string()];
  // The pace from two reports of one service, by their own stamps.
  const double wall = (s.stamp().wall_time_ns() - last.stamp().wall_time_ns()) * 1e-9;
  if (last.steps() > 0 && wall > 0 && s.stamp().sim_time_ns() >= sim_ns_) {
    factor_ = (s.stamp().sim_time_ns() - last.stamp().sim_time_ns()) * 1e-9 / wall;
    sim_ns_ = s.stamp().sim_time_ns();
  }
  const bool first = last.service().size() == 0;
  last = s;
  if (s.state().to_string() != "starting") ran_.insert(s.service().to_string());
  // What each service got of its scheduling, once (docs/haptic.md).
  if (first) scheduling_ += text("  %-16s scheduling: %s\n", s.service().c_str(), s.scheduling().c_str());
}

std::string Watcher::finish() {
  const bool end = tty_ && shown_;
  shown_ = false;
  return end ? "\n" : "";
}

std::string Watcher::update(double waited_s, std::int64_t now_ns) {
  std::string out;
  if (!scheduling_.empty()) out += finish() + std::exchange(scheduling_, "");
  if (!all_joined_) {
    std::string absent;
    {
      std::lock_guard<std::mutex> l(joined_mutex_);
      absent = missing(names_, [&](const std::string& n) { return joined_.count(n) > 0; });
    }
    if (absent.empty()) {
      all_joined_ = true;
      out += finish() + text("hcosim up: every service joined domain %d in %.2f s\n", domain_, waited_s);
    } else if (!join_warned_ && waited_s > kJoinWaitS) {
      join_warned_ = true;
      out += finish() + text("hcosim up: after %.0f s still no status from: ", kJoinWaitS) + absent + "\n";
    }
  }
  if (!all_running_) {
    const std::string starting = missing(names_, [&](const std::string& n) { return running(n); });
    if (starting.empty() || waited_s > kStartWaitS) {
      all_running_ = true;
      out += finish();
      if (starting.empty())
        out += text("hcosim up: every service running after %.2f s\n", waited_s);
      else
        out += text("hcosim up: after %.0f s still starting: ", kStartWaitS) + starting +
               "; the run goes on without waiting\n";
    } else if (!start_warned_ && all_joined_ && waited_s > kJoinWaitS) {
      start_warned_ = true;
      out += finish() + text("hcosim up: still starting after %.0f s: ", kJoinWaitS) + starting + "\n";
      std::lock_guard<std::mutex> l(joined_mutex_);
      for (const auto& [name, where] : joined_)
        if (!where.empty()) out += "hcosim up:   participant " + name + " " + where + "\n";
    }
  }
  return out + progress(now_ns);
}

// Simulated time, real-time factor, and each service's achieved rate and
// overruns, as one line.
std::string Watcher::progress(std::int64_t now_ns) {
  if (now_ns - printed_ns_ < (tty_ ? 500'000'000 : std::int64_t(kLogProgressS * 1e9)) || sim_ns_ == 0) return "";
  printed_ns_ = now_ns;
  std::string line = text("sim %.1f s, real-time factor %.2f", sim_ns_ * 1e-9, factor_);
  for (const auto& [name, s] : latest_)
    line += text(" | %s %.0f Hz, %llu overruns", name.c_str(), s.rate_achieved_hz(),
                 static_cast<unsigned long long>(s.overruns())) +
            (s.outputs_shed() ? text(", %llu shed", static_cast<unsigned long long>(s.outputs_shed())) : "");
  shown_ = true;
  return tty_ ? "\r" + line + "\033[K" : line + "\n";
}

}  // namespace hcosim::services::cli

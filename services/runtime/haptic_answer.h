// How a force source meets the device's states: in real time each
// HapticState is answered as it arrives, on the thread that receives it,
// never waiting on the service's loop; in lockstep the step waits for the
// device's state of the same step (the Gauss-Seidel group,
// docs/cosimulation.md).
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>

#include "services/runtime/service.h"

namespace hcosim::services::runtime {

// Calls answer(state) for every admissible HapticState of `device` as it
// arrives, on Fast DDS's receiving thread (Reader::on_arrival), never
// waiting on the service's loop. That thread has the scheduling of the
// thread that made the participant (realtime.h): the haptic priority, when
// the service raised itself before joining.
class AnswerOnArrival {
 public:
  using Answer = std::function<void(const HapticState&)>;
  AnswerOnArrival(Reader<HapticState>& in, std::string device, Answer answer)
      : in_(in), device_(std::move(device)), answer_(std::move(answer)) {
    in_.on_arrival([this] {
      in_.take([&](const HapticState& s) {
        if (s.device().to_string() == device_) answer_(s);
      });
    });
  }
  ~AnswerOnArrival() { stop(); }
  // No answer runs or follows once this returns.
  void stop() { in_.on_arrival(nullptr); }
  AnswerOnArrival(const AnswerOnArrival&) = delete;
  AnswerOnArrival& operator=(const AnswerOnArrival&) = delete;

 private:
  Reader<HapticState>& in_;
  std::string device_;
  Answer answer_;
};

// What a force source's answers cost and left out, for its closing lines.
struct AnswerStats {
  Window us{1 << 16};            // answering one state, every object of the source
  std::uint64_t unanswered = 0;  // (object, state) pairs left to a free-space answer
  // "SERVICE: N WHAT-states left to a free-space answer".
  void report_unanswered(std::FILE* out, const std::string& service, const char* what) const {
    std::fprintf(out, "%s: %llu %s-states left to a free-space answer\n", service.c_str(),
                 static_cast<unsigned long long>(unanswered), what);
  }
};

// The stamp of an answer computed on arrival: the step and simulated time
// of the state it answers, written now.
inline StepStamp answer_stamp(const HapticState& s) {
  StepStamp st = s.stamp();
  st.wall_time_ns(wall_ns());
  return st;
}

// Whether this service steps with `device` in one Gauss-Seidel group: a
// lockstep deployment that runs that haptic service at this service's
// rate (the device's side: force_sources at its rate). Otherwise its
// answers follow the Jacobi scheme (one step behind).
inline bool in_haptic_group(const Service& svc, const std::string& device) {
  if (svc.options().mode != adapters::Mode::kLockstep) return false;
  for (const adapters::ServiceSpec& s : svc.deployment().services)
    if (s.name == device && s.kind == "haptic" && s.unneeded.empty()) return s.rate_hz == svc.options().rate_hz;
  return false;
}

// Lockstep, in the group: takes `device`'s states up to this tick's step,
// waiting until the one of this step has come, f(state) for each; then,
// until `answers` reaches the device, waits for that too (an answer written
// before its writer matched the device's reader would be lost, and the
// device would wait for it forever).
template <class F>
void take_state_of_step(Service& svc, Reader<HapticState>& in, Writer<ForceFeedback>& answers, const Tick& tick,
                        const std::string& device, F&& f) {
  const std::int64_t deadline = mono_ns() + 10'000'000'000;
  const auto late = [&](const char* what) {
    return std::runtime_error(svc.options().name + ": step " + std::to_string(tick.step) + ": " + what + " '" + device +
                              "' after 10 s");
  };
  bool got = false;
  eprosima::fastrtps::rtps::InstanceHandle_t from;
  for (;;) {
    in.take_before(tick.step + 1, [&](const HapticState& s) {
      if (s.device().to_string() != device) return;
      got = got || s.stamp().step() == tick.step;
      from = in.current_writer();
      f(s);
    });
    if (got || stop_requested()) break;
    if (mono_ns() > deadline) throw late("no HapticState for this step from");
    in.wait(std::chrono::milliseconds(100));
  }
  while (got && !answers.reaches(from) && !stop_requested()) {
    if (mono_ns() > deadline) throw late("the answers' writer has not matched a reader of");
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Lockstep: passes `keep` each of `device`'s states this step sees: in its
// Gauss-Seidel group (`group`, in_haptic_group) the state of this step
// (take_state_of_step), otherwise those before it, one step behind.
template <class F>
void take_device_states(Service& svc, Reader<HapticState>& in, Writer<ForceFeedback>& answers, const Tick& tick,
                        const std::string& device, bool group, F&& keep) {
  const auto mine = [&](const HapticState& s) {
    if (s.device().to_string() == device) keep(s);
  };
  if (group)
    take_state_of_step(svc, in, answers, tick, device, mine);
  else
    svc.take(in, tick, mine);
}

}  // namespace hcosim::services::runtime

// The dds and haptic suites' baseline: a peer process answering
// HapticState with ForceFeedback, bare Fast DDS or hcosim's runtime, and
// round trips against it (defined in dds.cc).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include "services/runtime/stats.h"

namespace hcosim::services::bench {

// 1 kHz HapticState -> ForceFeedback round trips, us.
struct Rtt {
  runtime::Window us{1 << 20};
  runtime::Window late_us{1 << 20};  // the pinging loop's wake-up lateness: a bare timer's jitter beside the same load
  std::uint64_t sent = 0, lost = 0;
};

// A peer process answering HapticState with ForceFeedback: `impl` "bare"
// (Fast DDS alone) or "hcosim" (the service runtime), at SCHED_FIFO
// `priority` (0: the normal scheduler) as far as the system allows,
// behind the command `on` (another host's, Hosts::exec) if any, given
// `args` too (such as that host's --deployment and --host).
pid_t start_peer(const std::string& impl, int domain, double seconds, int priority = 0,
                 const std::vector<std::string>& on = {}, const std::vector<std::string>& args = {});
void stop_peer(pid_t pid);

// Round trips against a bare Fast DDS peer for `seconds`, both ends (and
// their Fast DDS threads) at `priority`.
Rtt bare_rtt(int domain, double seconds, int priority = 0);

}  // namespace hcosim::services::bench

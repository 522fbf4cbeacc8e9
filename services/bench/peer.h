// The baselines the suites measure hcosim against in the same run: bare
// Fast DDS endpoints with nothing of hcosim's, and a peer process
// (`hcosim bench-peer`) answering HapticState with ForceFeedback, bare or
// through hcosim's runtime, for 1 kHz round trips.
#pragma once

#include <sys/types.h>
#include <time.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "idl/haptic.h"
#include "services/runtime/network.h"
#include "services/runtime/service.h"
#include "services/runtime/stats.h"
#include "services/runtime/topics.h"

namespace hcosim::services::bench {

// 1 kHz HapticState -> ForceFeedback round trips, us.
struct Rtt {
  runtime::Window us{1 << 20};
  runtime::Window late_us{1 << 20};  // the pinging loop's wake-up lateness: a bare timer's jitter beside the same load
  std::uint64_t sent = 0, lost = 0;
};

// Default participant QoS (builtin transports) unless `mesh_transports`:
// then deploy/qos.xml's shared memory (8 MiB segment) and UDPv4, set in
// code, the UDP socket buffers and interface those of `network` (a rig's
// host, between hosts) where it names them.
eprosima::fastdds::dds::DomainParticipant* bare_participant(int domain, bool mesh_transports,
                                                            const runtime::Network& network = {});
// Deletes a bare participant and everything in it.
void destroy_bare(eprosima::fastdds::dds::DomainParticipant* p);

// The topic `name` of T's type on a bare participant.
template <class T>
eprosima::fastdds::dds::Topic* bare_topic(eprosima::fastdds::dds::DomainParticipant* p, const char* name) {
  eprosima::fastdds::dds::TypeSupport ts(new typename runtime::TopicOf<T>::PubSub());
  ts.register_type(p, runtime::TopicOf<T>::type_name);
  return p->create_topic(name, runtime::TopicOf<T>::type_name, eprosima::fastdds::dds::TOPIC_QOS_DEFAULT);
}

// Sleeps until CLOCK_MONOTONIC reaches `mono_ns`.
inline void sleep_until(std::int64_t mono_ns) {
  const timespec ts{time_t(mono_ns / 1'000'000'000), long(mono_ns % 1'000'000'000)};
  clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
}

// Sends HapticState at 1 kHz for `seconds`, waiting up to 10 ms for the
// ForceFeedback that answers each one.
template <class Wait, class Take, class Write>
Rtt ping(double seconds, Wait&& wait, Take&& take, Write&& write) {
  Rtt r;
  HapticState s;
  s.device("bench");
  s.orientation().w(1.0);
  const std::int64_t period = 1'000'000, start = runtime::mono_ns();
  const std::uint64_t n = std::uint64_t(seconds * 1000);
  for (std::uint64_t k = 0; k < n; ++k) {
    sleep_until(start + std::int64_t(k) * period);
    r.late_us.add((runtime::mono_ns() - start - std::int64_t(k) * period) * 1e-3);
    s.seq(k);
    s.position().z(1e-3 * double(k % 10));
    const std::int64_t t0 = runtime::mono_ns();
    write(s);
    ++r.sent;
    bool answered = false;
    while (!answered && runtime::mono_ns() - t0 < 10'000'000)
      if (wait()) answered = take(k);
    if (answered)
      r.us.add((runtime::mono_ns() - t0) * 1e-3);
    else
      ++r.lost;
  }
  return r;
}

// Waits up to 10 s for `want` matches on both counts.
void await_match(const std::function<int()>& writers_readers, int want);

// A peer process answering HapticState with ForceFeedback: `impl` "bare"
// (Fast DDS alone) or "hcosim" (the service runtime), at SCHED_FIFO
// `priority` (0: the normal scheduler) as far as the system allows,
// behind the command `on` (another host's, Hosts::exec) if any, given
// `args` too (such as that host's --deployment and --host). Stop it with
// stop() (harness.h).
pid_t start_peer(const std::string& impl, int domain, double seconds, int priority = 0,
                 const std::vector<std::string>& on = {}, const std::vector<std::string>& args = {});

// Round trips from this thread for `seconds` against a bare peer already
// running on `domain` (start_peer).
Rtt bare_ping(int domain, double seconds);

// Round trips against a bare Fast DDS peer for `seconds`, both ends (and
// their Fast DDS threads) at `priority`.
Rtt bare_rtt(int domain, double seconds, int priority = 0);

// The bench-peer command's readers of large samples (dds.cc): `role` mesh
// (DeformedMesh) or frame (CameraFrame), through `impl` bare or hcosim,
// until the last of `count` arrives or `end` (CLOCK_MONOTONIC ns); what
// it saw is written to `out`.
int read_large(const std::string& role, const std::string& impl, int domain, int count, const std::string& out,
               std::int64_t end, const runtime::Network& network);

}  // namespace hcosim::services::bench

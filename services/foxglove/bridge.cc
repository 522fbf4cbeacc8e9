#include "services/foxglove/bridge.h"

#include <malloc.h>

#include <cstdio>
#include <thread>
#include <type_traits>

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <opencv2/core/utility.hpp>

#include "adapters/validate.h"
#include "adapters/vision/media.h"
#include "services/recording/recording.h"
#include "services/runtime/service.h"
#include "services/runtime/topics.h"
#include "services/runtime/transport.h"

namespace hcosim::services::foxglove {

namespace {

// The time a sample's messages carry: its stamp's wall time, else now.
template <class T>
std::uint64_t time_of(const T& s) {
  if constexpr (recording::detail::HasStamp<T>::value) {
    if (s.stamp().wall_time_ns() > 0) return std::uint64_t(s.stamp().wall_time_ns());
  }
  return std::uint64_t(runtime::wall_ns());
}

// Whether `p` has a shared-memory transport of its own (hcosim's QoS
// profile; not a network section's udp_only), under which UDP is a
// UdpBesideShm whose threads say so.
bool has_shared_memory(runtime::Participant& p) {
  for (const auto& t : p.dds()->get_qos().transport().user_transports)
    if (std::dynamic_pointer_cast<eprosima::fastdds::rtps::SharedMemTransportDescriptor>(t)) return true;
  return false;
}

}  // namespace

Bridge::Bridge(runtime::Participant& p, Server& server, std::vector<adapters::foxglove::Item> items,
               adapters::foxglove::Options o)
    : server_(server), builder_(std::move(items), o) {
  adapters::vision::load_media();
  // A 640x480 frame gains nothing from OpenCV's thread pool, whose
  // workers wake for each colour conversion and spin after it.
  cv::setNumThreads(1);
  server_.every_flush([this] { draw(); });
  runtime::for_each_topic([&](auto tag) {
    using T = typename decltype(tag)::type;
    using Topic = runtime::TopicOf<T>;
    const std::uint32_t raw =
        server_.advertise({Topic::name, "cdr", Topic::type_name, recording::idl_schema(Topic::type_name), "omgidl"});
    // Best effort ("control"): no writer waits for this reader. The latched
    // topology stays reliable and durable, as a mesh cannot be drawn without it.
    const std::string profile = std::is_same_v<T, MeshTopology> ? Topic::qos : "control";
    auto reader = std::make_shared<runtime::Reader<T>>(
        p, [](const T& s) { return adapters::validate(s); }, &rejections_, profile, runtime::kMonitorDepth);
    // The sample is the reader's own, read into afresh by its next take:
    // take() may move from it.
    auto take_all = [this, r = reader.get(), raw] {
      r->take([&](T& s) { take(s, raw); });
      rest();
    };
    reader->on_arrival(take_all);
    stops_.push_back([reader] { reader->on_arrival(nullptr); });
  });
  // Only now: a thread resting in a listener holds Fast DDS's locks on the
  // message it is receiving, which adding a reader waits for (resting from
  // the first reader on, the bridge said it served 3.4 s after its log
  // opened at the default scene, 2.4 s so; one run each, by hand).
  rests_ = has_shared_memory(p);
}

Bridge::~Bridge() {
  for (auto& stop : stops_) stop();
  server_.every_flush(nullptr);
}

std::uint32_t Bridge::scene_channel(const adapters::foxglove::ChannelOf& c) {
  std::lock_guard<std::mutex> l(channels_m_);
  const auto it = scene_channels_.find(c.topic);
  if (it != scene_channels_.end()) return it->second;
  const std::uint32_t id = server_.advertise({c.topic, "cdr", c.schema, adapters::foxglove::schema_text(), "omgidl"});
  scene_channels_.emplace(c.topic, id);
  return id;
}

template <class T>
void Bridge::take(T& s, std::uint32_t raw) {
  ++samples_;
  const std::uint64_t t = time_of(s);
  if (t > newest_ns_) newest_ns_ = t;
  if (server_.subscribed(raw)) {
    std::string framed(Server::kHeadroom, '\0');
    recording::append_cdr(s, framed);
    server_.publish_framed(raw, t, std::move(framed));
  }
  if constexpr (std::is_same_v<T, MeshTopology>) {
    std::lock_guard<std::mutex> l(m_);
    topologies_.push_back([s](adapters::foxglove::Builder& b) { return b.on(s); });
  } else {
    const adapters::foxglove::ChannelOf c = builder_.channel(s);
    if (c.topic.empty()) return;
    const std::uint32_t id = scene_channel(c);
    if (!server_.subscribed(id)) return;
    // No wake-up: the socket thread draws it when it next sends.
    // Moved, not copied: a camera frame is 900 KB, 25 times a second.
    auto taken = std::make_shared<const T>(std::move(s));
    std::lock_guard<std::mutex> l(m_);
    auto& slot = pending_[id];
    if (slot.first) ++skipped_;
    slot = {[taken](adapters::foxglove::Builder& b) { return b.on(*taken); }, t};
  }
}

void Bridge::rest() {
  if (!rests_ || runtime::receives_udp() || runtime::writing()) return;
  if (runtime::mono_ns() - rested_ns_ < kAwakeNs) return;
  std::this_thread::sleep_for(std::chrono::nanoseconds(kRestNs));
  rested_ns_ = runtime::mono_ns();
}

void Bridge::draw() {
  std::vector<Draw> topologies;
  std::map<std::uint32_t, std::pair<Draw, std::uint64_t>> pending;
  {
    std::lock_guard<std::mutex> l(m_);
    topologies.swap(topologies_);
    pending.swap(pending_);
  }
  try {
    for (const Draw& d : topologies) d(builder_);
    for (auto& [id, work] : pending) {
      for (adapters::foxglove::Message& m : work.first(builder_)) {
        ++drawn_;
        server_.publish(id, work.second, m.cdr);
      }
    }
    unmatched_ = builder_.unmatched();
  } catch (const std::exception& e) {
    // A sample the scene cannot draw (validated, so a bug): said, and the rest goes on.
    std::fprintf(stderr, "foxglove: cannot draw a scene message: %s\n", e.what());
  }
}

void Bridge::tick() {
  const std::uint64_t t = newest_ns_;
  if (t != told_ns_.exchange(t)) server_.time(t);
}

BridgeCounters Bridge::counters() const {
  BridgeCounters c;
  c.samples = samples_, c.drawn = drawn_, c.skipped = skipped_, c.unmatched = unmatched_;
  std::lock_guard<std::mutex> l(rejections_.m);
  c.refused = rejections_.count;
  return c;
}

void keep_freed_memory() {
  // Camera frames (900 KB) pass through a bridge 25 times a second, copied
  // on three threads. glibc's defaults map each such buffer afresh and
  // give freed ones back to the kernel, so every copy faulted its pages
  // in again: half the bridge's CPU time (docs/foxglove.md, "Measured").
  mallopt(M_MMAP_THRESHOLD, 16 << 20);
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
}

std::string summary(const Server& server, const Bridge& bridge) {
  const ServerCounters s = server.counters();
  const BridgeCounters b = bridge.counters();
  char line[512];
  std::snprintf(line, sizeof line,
                "%llu samples taken, %llu refused; %llu scene messages drawn, %llu samples skipped for newer ones, "
                "%llu meshes without a topology; %llu connections, %llu messages sent (%.1f MB), %llu held back "
                "from clients over their limit, %llu dropped with the outbox full, %llu slow clients closed, %llu "
                "requests refused",
                (unsigned long long)b.samples, (unsigned long long)b.refused, (unsigned long long)b.drawn,
                (unsigned long long)b.skipped, (unsigned long long)b.unmatched, (unsigned long long)s.connections,
                (unsigned long long)s.sent, s.bytes / 1e6, (unsigned long long)s.held_back,
                (unsigned long long)s.outbox_dropped, (unsigned long long)s.slow_closed, (unsigned long long)s.refused);
  return line;
}

}  // namespace hcosim::services::foxglove

// A live Foxglove bridge (docs/foxglove.md): every topic of a DDS domain
// as a channel of its CDR bytes with its OMG IDL schema, and Foxglove's
// scene channels (adapters/foxglove/panels.h) drawn from the topics, served
// by a Server. Only what a client subscribes to is serialised or drawn.
//
// Nothing here slows a DDS writer: the readers are best effort (but the
// latched topology), so no writer waits on their acknowledgements, even
// in lockstep; on Fast DDS's receiving threads a sample is copied to the
// server's outbox or kept for drawing. The server's socket thread draws,
// each time it wakes to send, only each scene channel's latest sample (a
// slower drawing skips samples, counted): a thread of its own would add
// its wake-ups, which cost more than the drawing on a virtual machine
// (docs/PERFORMANCE.md, "The live Foxglove bridge").
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "adapters/foxglove/panels.h"
#include "services/foxglove/server.h"
#include "services/runtime/endpoint.h"
#include "services/runtime/participant.h"

namespace hcosim::services::foxglove {

struct BridgeCounters {
  std::uint64_t samples = 0;    // taken from the topics (admissible ones)
  std::uint64_t refused = 0;    // samples validation refused (NaN, absurd values): neither sent nor drawn
  std::uint64_t drawn = 0;      // scene messages drawn
  std::uint64_t skipped = 0;    // samples a scene channel's next sample replaced before it was drawn
  std::uint64_t unmatched = 0;  // meshes not drawn for want of their topology
};

class Bridge {
 public:
  // Advertises the topics at once and each scene channel when its first
  // sample arrives. `server` outlives the bridge.
  Bridge(runtime::Participant& p, Server& server, std::vector<adapters::foxglove::Item> items,
         adapters::foxglove::Options o);
  ~Bridge();  // stops the readers, then the drawing
  Bridge(const Bridge&) = delete;
  Bridge& operator=(const Bridge&) = delete;

  // Tells the clients the newest sample's time (the protocol's time).
  void tick();
  BridgeCounters counters() const;

 private:
  // One sample to draw, with the time of the messages it gives.
  using Draw = std::function<std::vector<adapters::foxglove::Message>(adapters::foxglove::Builder&)>;

  // Takes `s` over: its bytes go to draw() without a copy.
  template <class T>
  void take(T& s, std::uint32_t raw);
  std::uint32_t scene_channel(const adapters::foxglove::ChannelOf& c);
  void draw();  // on the server's socket thread
  // After a take on a receiving thread of shared memory: once it has been
  // awake kAwakeNs since it last rested, it rests kRestNs, and what
  // arrives meanwhile waits in the port's queue (1,024 deep, deploy/qos.xml)
  // to be taken in one wake-up. Fast DDS wakes that thread for every
  // sample, over a thousand times a second at the default scene, and on a
  // virtual machine the wake-ups cost more than the samples' work; the
  // clients are sent to every 10 ms anyway (bench foxglove measures the
  // bridge's CPU share). Never on UDP's threads (runtime::receives_udp), nor
  // on the thread of a writer in this process (runtime::writing), on which
  // Fast DDS hands its samples to the bridge's readers.
  void rest();
  static constexpr std::int64_t kRestNs = 5'000'000, kAwakeNs = 1'000'000;

  Server& server_;
  adapters::foxglove::Builder builder_;  // draw()'s, but channel()
  runtime::Rejections rejections_;

  std::mutex channels_m_;
  std::map<std::string, std::uint32_t> scene_channels_;  // by topic

  std::mutex m_;                                                     // what waits for draw()
  std::vector<Draw> topologies_;                                     // every one, in order
  std::map<std::uint32_t, std::pair<Draw, std::uint64_t>> pending_;  // by channel: its latest sample, and its time

  std::atomic<std::uint64_t> samples_{0}, drawn_{0}, skipped_{0}, unmatched_{0}, newest_ns_{0}, told_ns_{0};
  std::atomic<bool> rests_{false};            // made, with shared memory: rest() may rest
  std::atomic<std::int64_t> rested_ns_{0};    // when the last rest ended (mono)
  std::vector<std::function<void()>> stops_;  // each reader's, owning it
};

// For a process that runs a bridge, before it starts: buffers up to 16 MB
// come from the heap and freed memory is kept for the next camera frame,
// where glibc's defaults map each large buffer afresh.
void keep_freed_memory();

// One line of what a bridge and its server did, for a closing line.
std::string summary(const Server& server, const Bridge& bridge);

}  // namespace hcosim::services::foxglove

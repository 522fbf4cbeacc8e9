// A Foxglove WebSocket protocol server (foxglove.websocket.v1; docs/foxglove.md):
// it advertises channels, takes clients' subscriptions and sends each
// subscribed channel's messages as binary frames. No DDS here: the bridge
// (services/foxglove/bridge.h) gives it channels and messages.
//
// Threads: one of its own runs the sockets. publish() and time() may be
// called from any thread and never block on a client: messages wait in an
// outbox bounded in bytes, and a client whose socket takes less than it is
// sent is given no more messages while its unsent bytes exceed a limit,
// and is closed when they stay over half that limit for slow_client_s
// after passing it.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "adapters/foxglove/bridge_config.h"

namespace hcosim::services::foxglove {

// A channel as the protocol's advertise message names it.
struct Channel {
  std::string topic;
  std::string encoding;         // "cdr"
  std::string schema_name;      // e.g. "hcosim::DeformedMesh", "foxglove::SceneUpdate"
  std::string schema;           // its text
  std::string schema_encoding;  // "omgidl"
};

struct ServerOptions {
  // The interface to listen on, the port (0: any free one, port() says
  // which), and a client's unsent bytes above which it gets no more
  // messages: the bridge service's defaults.
  std::string address = adapters::foxglove::BridgeConfig().address;
  int port = adapters::foxglove::BridgeConfig().port;
  std::size_t client_limit_bytes = adapters::foxglove::BridgeConfig().client_limit_bytes;
  std::string name = "hcosim";  // serverInfo's name
  // The kernel's send buffer of each client's socket (SO_SNDBUF): capped,
  // so that a client that stops reading shows as unsent bytes here within
  // a few hundred kB, not after megabytes queued by the kernel's tuning.
  int socket_buffer_bytes = 256 << 10;
  double slow_client_s = 2;  // a client over its limit, and since then never under half of it, this long is closed
  std::size_t outbox_limit_bytes = 64000000;  // messages waiting for the socket thread
};

// What the server has done, for a service's closing line and the bench.
struct ServerCounters {
  std::uint64_t clients = 0;         // connected now
  std::uint64_t connections = 0;     // ever accepted
  std::uint64_t sent = 0;            // messages sent to a client (one per subscription)
  std::uint64_t bytes = 0;           // their frames' bytes
  std::uint64_t held_back = 0;       // messages a client over its limit was not sent
  std::uint64_t outbox_dropped = 0;  // messages dropped because the outbox was full
  std::uint64_t slow_closed = 0;     // clients closed for staying over their limit
  std::uint64_t refused = 0;         // client requests answered with an error status
};

class Server {
 public:
  // Listens at once. Throws std::runtime_error naming address:port when it
  // cannot (in use, no such interface), std::invalid_argument for options
  // out of range.
  explicit Server(ServerOptions o);
  ~Server();  // closes every client and stops the socket thread
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  int port() const;  // the port listened on
  const std::string& address() const;

  // Adds a channel and advertises it to the clients; returns its id. Any thread.
  std::uint32_t advertise(const Channel& c);
  // Whether any client subscribes to `channel`: publish only then. Lock-free.
  bool subscribed(std::uint32_t channel) const;
  // Sends `data` to each client subscribed to `channel`, stamped `time_ns`.
  // Any thread; returns at once.
  void publish(std::uint32_t channel, std::uint64_t time_ns, const std::vector<std::uint8_t>& data);
  // As publish(), for data already behind kHeadroom free bytes, where the
  // protocol's header goes: the bytes reach a client's socket uncopied (a
  // 640x480 camera frame at 30 Hz is 28 MB/s).
  void publish_framed(std::uint32_t channel, std::uint64_t time_ns, std::string framed);
  static constexpr std::size_t kHeadroom = 13;  // op (1), subscription id (4), time (8)
  // The server's clock (the protocol's time message), in the messages' time base.
  void time(std::uint64_t time_ns);
  // Has the socket thread call `f` every time it wakes to send what waits
  // (every 10 ms), before sending: work whose messages go out then needs
  // no thread, nor wake-ups, of its own. nullptr: no more calls; returns
  // once none is running. Not from within `f`.
  void every_flush(std::function<void()> f);

  ServerCounters counters() const;

  static constexpr std::size_t kMaxChannels = 256;
  static constexpr const char* kSubprotocol = "foxglove.websocket.v1";

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hcosim::services::foxglove

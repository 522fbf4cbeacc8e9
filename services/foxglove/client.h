// A minimal foxglove.websocket.v1 client: it subscribes to every channel a
// server advertises and counts what arrives. The bench's client
// "subscribed to everything" (services/bench/foxglove.cc).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

namespace hcosim::services::foxglove {

struct ClientCounts {
  bool open = false;
  std::uint64_t channels = 0;  // advertised, each subscribed
  std::uint64_t messages = 0;  // message frames received
  std::uint64_t bytes = 0;     // their payloads' bytes
  std::uint64_t statuses = 0;  // status messages (the server's errors and warnings)
  std::map<std::string, std::uint64_t> per_topic;
};

class Client {
 public:
  // Connects to ws://ADDRESS:PORT and runs until destroyed.
  Client(const std::string& address, int port);
  ~Client();
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;
  ClientCounts counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hcosim::services::foxglove

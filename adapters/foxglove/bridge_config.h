// The live Foxglove bridge's params (docs/foxglove.md): where it listens,
// how much a slow client may fall behind, and how the panels are drawn.
#pragma once

#include <cstddef>
#include <string>

#include "adapters/config.h"
#include "adapters/foxglove/panels.h"
#include "adapters/scene.h"

namespace hcosim::adapters::foxglove {

struct BridgeConfig {
  std::string address = "127.0.0.1";         // the interface to listen on
  int port = 8765;                           // 0: any free port
  std::size_t client_limit_bytes = 8000000;  // a client's unsent bytes above which it gets no more messages
  Options panels;                            // the world frame on the scene's marker
};

// `marker`: the scene's, whose id is the world frame's tag. Throws
// adapters::ConfigError at FILE:LINE:COL for an unknown key or a value out
// of range.
BridgeConfig bridge_config(const Config& params, const MarkerSpec& marker);

}  // namespace hcosim::adapters::foxglove

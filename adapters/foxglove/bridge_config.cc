#include "adapters/foxglove/bridge_config.h"

namespace hcosim::adapters::foxglove {

BridgeConfig bridge_config(const Config& p, const MarkerSpec& marker) {
  p.allow_only({"port", "address", "jpeg_quality", "scene_rate", "client_limit_mb"});
  BridgeConfig b;
  b.port = p.whole("port", b.port, 0, 65535);
  b.address = p.string("address", b.address);
  b.client_limit_bytes = std::size_t(p.number("client_limit_mb", b.client_limit_bytes / 1e6, 0.01, 1e4) * 1e6);
  b.panels.tag_id = marker.id.value_or(b.panels.tag_id);
  b.panels.jpeg_quality = p.whole("jpeg_quality", b.panels.jpeg_quality, 0, 100);
  b.panels.rate_hz = p.number("scene_rate", b.panels.rate_hz, 1, 1000);
  return b;
}

}  // namespace hcosim::adapters::foxglove

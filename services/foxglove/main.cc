// hcosim_foxglove: the live Foxglove bridge as a service of a deployment
// (kind foxglove; docs/foxglove.md). It serves the domain's topics and the
// scene's Foxglove channels over the Foxglove WebSocket protocol, and
// steps only to tell its clients the time. It observes: in lockstep it
// runs on the wall clock and the lockstep clock does not wait for it.
#include <cstdio>

#include "services/foxglove/bridge.h"
#include "services/foxglove/panels.h"
#include "services/runtime/service.h"

using namespace hcosim;
using namespace hcosim::services;

int main(int argc, char** argv) {
  foxglove::keep_freed_memory();
  return runtime::service_main(
      "hcosim_foxglove", "the live Foxglove bridge: topics and scene channels over foxglove.websocket.v1", argc, argv,
      [](runtime::Options options) {
        options.mode = adapters::Mode::kRealtime;
        runtime::Service svc(options);
        const adapters::Config& c = svc.params();
        c.allow_only({"port", "address", "jpeg_quality", "scene_rate", "client_limit_mb"});
        foxglove::ServerOptions so;
        so.port = c.whole("port", so.port, 0, 65535);
        so.address = c.string("address", so.address);
        so.client_limit_bytes = std::size_t(c.number("client_limit_mb", so.client_limit_bytes / 1e6, 0.01, 1e4) * 1e6);
        adapters::foxglove::Options scene;
        scene.tag_id = foxglove::marker_id(svc.deployment());
        scene.jpeg_quality = c.whole("jpeg_quality", scene.jpeg_quality, 0, 100);
        scene.rate_hz = c.number("scene_rate", scene.rate_hz, 1, 1000);
        foxglove::Server server(so);
        foxglove::Bridge bridge(svc.participant(), server, foxglove::panel_items(svc.deployment()), scene);
        const std::string& name = svc.options().name;
        std::printf("%s: serving ws://%s:%d (foxglove.websocket.v1)\n", name.c_str(), server.address().c_str(),
                    server.port());
        std::fflush(stdout);
        const int status = svc.run([&](const runtime::Tick&) { bridge.tick(); });
        std::printf("%s: %s\n", name.c_str(), foxglove::summary(server, bridge).c_str());
        return status;
      });
}

// hcosim_foxglove: the live Foxglove bridge as a service of a deployment
// (kind foxglove; docs/foxglove.md). It serves the domain's topics and the
// scene's Foxglove channels over the Foxglove WebSocket protocol, and
// steps only to tell its clients the time. It observes: in lockstep it
// runs on the wall clock and the lockstep clock does not wait for it.
#include <cstdio>

#include "adapters/foxglove/bridge_config.h"
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
        const adapters::foxglove::BridgeConfig config =
            adapters::foxglove::bridge_config(svc.params(), svc.deployment().scene.marker);
        foxglove::ServerOptions so;
        so.port = config.port;
        so.address = config.address;
        so.client_limit_bytes = config.client_limit_bytes;
        foxglove::Server server(so);
        foxglove::Bridge bridge(svc.participant(), server, foxglove::panel_items(svc.deployment()), config.panels);
        const std::string& name = svc.options().name;
        std::printf("%s: serving ws://%s:%d (foxglove.websocket.v1)\n", name.c_str(), server.address().c_str(),
                    server.port());
        std::fflush(stdout);
        const int status = svc.run([&](const runtime::Tick&) { bridge.tick(); });
        std::printf("%s: %s\n", name.c_str(), foxglove::summary(server, bridge).c_str());
        return status;
      });
}

// hcosim foxglove: the live Foxglove bridge (services/foxglove/bridge.h)
// for whatever runs on a domain, until its duration or Ctrl-C.
#include <chrono>
#include <cstdio>
#include <thread>

#include "services/cli/cli.h"
#include "services/foxglove/bridge.h"
#include "services/foxglove/panels.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {
namespace {

struct FoxgloveOptions {
  foxglove::ServerOptions server;
  std::string deployment;  // its scene's objects and marker
  double duration_s = 0;
  runtime::DdsOptions dds;
};

int serve(const FoxgloveOptions& o) {
  foxglove::keep_freed_memory();
  runtime::install_stop_handlers();
  adapters::foxglove::Options scene;
  std::vector<adapters::foxglove::Item> items;
  if (!o.deployment.empty()) {
    const adapters::Deployment d = adapters::load_deployment(o.deployment);
    items = foxglove::panel_items(d), scene.tag_id = d.scene.marker.id.value_or(scene.tag_id);
  }
  runtime::Participant p(o.dds.domain, "hcosim_foxglove", runtime::default_qos_file(), nullptr, false, o.dds.security);
  foxglove::Server server(o.server);
  foxglove::Bridge bridge(p, server, std::move(items), scene);
  std::printf("hcosim foxglove: serving domain %d at ws://%s:%d (foxglove.websocket.v1)\n", o.dds.domain,
              server.address().c_str(), server.port());
  std::fflush(stdout);
  const std::int64_t end = o.duration_s > 0 ? runtime::mono_ns() + std::int64_t(o.duration_s * 1e9) : INT64_MAX;
  while (!runtime::stop_requested() && runtime::mono_ns() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    bridge.tick();
  }
  std::printf("hcosim foxglove: %s\n", foxglove::summary(server, bridge).c_str());
  return 0;
}

}  // namespace

void add_foxglove(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<FoxgloveOptions>();
  CLI::App* c = app.add_subcommand("foxglove",
                                   "serve a domain's topics and Foxglove's scene channels to Foxglove over its "
                                   "WebSocket protocol (docs/foxglove.md)");
  c->add_option("--port", o->server.port, "the port to listen on (default 8765; 0: any free one)")
      ->option_text("P")
      ->check(CLI::Range(0, 65535).description(""));
  c->add_option("--address", o->server.address,
                "the address to listen on (default 127.0.0.1: this machine only; 0.0.0.0: every interface)")
      ->option_text("A");
  c->add_option("--deployment", o->deployment, "draw this deployment's scene objects (rigid bodies need their size)")
      ->option_text("FILE")
      ->check(CLI::ExistingFile);
  c->add_option("--duration", o->duration_s, "serve for S seconds (0: until Ctrl-C)")
      ->option_text("S")
      ->check(runtime::within(0, 1e9));
  runtime::add_dds(*c, o->dds);
  c->callback([&chosen, o] { chosen = [o] { return serve(*o); }; });
}

}  // namespace hcosim::services::cli

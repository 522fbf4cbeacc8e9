// hcosim: one entry point for running, inspecting and measuring deployments.
#include "services/bench/bench.h"
#include "services/cli/cli.h"

int main(int argc, char** argv) {
  using namespace hcosim::services;
  CLI::App app("one entry point for running, inspecting and measuring deployments", "hcosim");
  runtime::use_hcosim_help(app);
  app.footer(
      "The domain defaults to $HCOSIM_DOMAIN, else 0. Topics: docs/topics.md.\n"
      "topics, echo, hz, record and replay join a secure domain with --security DIR\n"
      "(else $HCOSIM_SECURITY) as --identity NAME (default hcosim).\n"
      "hcosim COMMAND --help describes each option of a command.");
  runtime::Command chosen;
  cli::add_up(app, chosen);
  cli::add_topics(app, chosen);
  cli::add_echo(app, chosen);
  cli::add_hz(app, chosen);
  cli::add_record(app, chosen);
  cli::add_foxglove(app, chosen);
  cli::add_export(app, chosen);
  cli::add_replay(app, chosen);
  bench::add_bench(app, chosen);
  cli::add_track(app, chosen);
  cli::add_synth(app, chosen);
  cli::add_video(app, chosen);
  cli::add_security(app, chosen);
  bench::add_peer(app, chosen);
  return runtime::run_command_line(app, argc, argv, chosen);
}

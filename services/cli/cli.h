// Subcommands of the hcosim command-line tool. Each add_NAME defines its
// command on the tool's CLI11 app (options, help) and, when the command
// line chooses it, sets `chosen` to run it.
#pragma once

#include "services/runtime/args.h"

namespace hcosim::services::cli {

using runtime::Command;

void add_up(CLI::App& app, Command& chosen);
void add_topics(CLI::App& app, Command& chosen);
void add_echo(CLI::App& app, Command& chosen);
void add_hz(CLI::App& app, Command& chosen);
void add_record(CLI::App& app, Command& chosen);
void add_export(CLI::App& app, Command& chosen);
void add_replay(CLI::App& app, Command& chosen);
void add_track(CLI::App& app, Command& chosen);
void add_synth(CLI::App& app, Command& chosen);
void add_video(CLI::App& app, Command& chosen);
void add_security(CLI::App& app, Command& chosen);
void add_foxglove(CLI::App& app, Command& chosen);

}  // namespace hcosim::services::cli

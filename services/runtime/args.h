// Command lines of the hcosim tool and of every service, defined once with
// CLI11: the definition gives the parser, the errors and the help text (the
// README's usage block is `hcosim --help`, checked by usage.readme).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "services/runtime/security.h"

namespace hcosim::services::runtime {

// What a command line chose to run: set by its subcommand's callback.
using Command = std::function<int()>;

// The options every DDS tool shares: --domain D (else $HCOSIM_DOMAIN,
// else 0), --security DIR (else $HCOSIM_SECURITY, else off) and
// --identity NAME (default "hcosim"; docs/security.md).
struct DdsOptions {
  int domain = 0;
  Security security{"", kToolIdentity};
};
void add_dds(CLI::App& app, DdsOptions& o);

// --domain D alone (a tool that joins no secure domain).
CLI::Option* add_domain(CLI::App& app, int& domain);

// --topics T1,T2: topics of the contract (none given: every topic).
void add_topic_list(CLI::App& app, std::vector<std::string>& topics);

// A topic name of the contract (docs/topics.md), for a TOPIC positional.
CLI::Validator topic_name();

// A finite number in [lo, hi] (CLI11's Range lets NaN through).
CLI::Validator within(double lo, double hi);

// `app` with hcosim's help layout: "usage: PROGRAM SYNOPSIS" from the
// options as defined, and a root that lists each command by its synopsis.
void use_hcosim_help(CLI::App& app);

// Parses the command line into `app` and runs what it chose inside
// guarded_main: --help prints help and returns 0; no command, or a
// command-line error, prints "PROGRAM: what" and returns 2.
int run_command_line(CLI::App& app, int argc, const char* const* argv, const Command& chosen);

}  // namespace hcosim::services::runtime

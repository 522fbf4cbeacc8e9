// Subcommands of the hcosim command-line tool.
#pragma once

#include <string>
#include <vector>

#include "services/runtime/args.h"

namespace hcosim::services::cli {

using runtime::Args;
using runtime::domain_of;
using runtime::parse;
using runtime::security_of;
using runtime::topics_of;

int up(const std::vector<std::string>& argv);
int topics(const std::vector<std::string>& argv);
int echo(const std::vector<std::string>& argv);
int hz(const std::vector<std::string>& argv);
int record(const std::vector<std::string>& argv);
int track(const std::vector<std::string>& argv);
int synth(const std::vector<std::string>& argv);
int video(const std::vector<std::string>& argv);
int export_recording(const std::vector<std::string>& argv);
int replay(const std::vector<std::string>& argv);
int security(const std::vector<std::string>& argv);

}  // namespace hcosim::services::cli

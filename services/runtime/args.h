// Arguments of the hcosim tool's subcommands: positionals, --flag VALUE,
// --switch, and the options every DDS tool shares.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

#include "services/runtime/security.h"

namespace hcosim::services::runtime {

// Parsed arguments of one subcommand: positionals, --flag VALUE, --switch.
struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> flags;
  std::set<std::string> switches;

  bool has(const std::string& f) const { return flags.count(f) || switches.count(f); }
  std::string get(const std::string& f, const std::string& fallback) const;
  double number(const std::string& f, double fallback) const;  // throws std::invalid_argument
  // A whole number in lo..hi; throws std::invalid_argument naming the range.
  int whole(const std::string& f, int fallback, int lo, int hi) const;
};

// Throws std::invalid_argument naming an unknown option or a missing value.
Args parse(const std::vector<std::string>& argv, const std::set<std::string>& flags,
           const std::set<std::string>& switches);

// Domain from --domain, else $HCOSIM_DOMAIN, else 0.
int domain_of(const Args& a);

// DDS Security for a tool: --security DIR, else $HCOSIM_SECURITY, else
// off; as --identity NAME, else "hcosim" (docs/security.md).
Security security_of(const Args& a);

// The topics named by --topics T1,T2 (none: every topic); throws
// std::invalid_argument naming one that is not in the contract.
std::vector<std::string> topics_of(const Args& a);

}  // namespace hcosim::services::runtime

// Arguments of the hcosim tool's subcommands.
#include "services/runtime/args.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

#include "services/runtime/participant.h"
#include "services/runtime/topics.h"

namespace hcosim::services::runtime {

std::string Args::get(const std::string& f, const std::string& fallback) const {
  auto it = flags.find(f);
  return it == flags.end() ? fallback : it->second;
}

double Args::number(const std::string& f, double fallback) const {
  auto it = flags.find(f);
  if (it == flags.end()) return fallback;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !std::isfinite(v))
    throw std::invalid_argument(f + " needs a number, not '" + it->second + "'");
  return v;
}

int Args::whole(const std::string& f, int fallback, int lo, int hi) const {
  const double v = number(f, fallback);
  if (v != std::floor(v) || v < lo || v > hi)
    throw std::invalid_argument(f + " must be a whole number in " + std::to_string(lo) + ".." + std::to_string(hi));
  return int(v);
}

Args parse(const std::vector<std::string>& argv, const std::set<std::string>& flags,
           const std::set<std::string>& switches) {
  Args a;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    const std::string& s = argv[i];
    if (s.rfind("--", 0) != 0) {
      a.positional.push_back(s);
    } else if (switches.count(s)) {
      a.switches.insert(s);
    } else if (flags.count(s)) {
      if (i + 1 >= argv.size()) throw std::invalid_argument(s + " needs a value");
      a.flags[s] = argv[++i];
    } else {
      throw std::invalid_argument("unknown option " + s);
    }
  }
  return a;
}

int domain_of(const Args& a) {
  const char* env = std::getenv("HCOSIM_DOMAIN");
  const double d = a.number("--domain", env && *env ? std::atof(env) : 0.0);
  if (d != std::floor(d) || d < 0 || d > kMaxDomain)
    throw std::invalid_argument("--domain must be a whole number in 0.." + std::to_string(kMaxDomain));
  return static_cast<int>(d);
}

Security security_of(const Args& a) {
  const char* env = std::getenv("HCOSIM_SECURITY");
  Security s{a.get("--security", env ? env : ""), a.get("--identity", kToolIdentity)};
  if (s.identity.empty()) throw std::invalid_argument("--identity needs a name");
  return s;
}

std::vector<std::string> topics_of(const Args& a) {
  std::vector<std::string> topics;
  std::stringstream list(a.get("--topics", ""));
  for (std::string t; std::getline(list, t, ',');) {
    if (t.empty()) continue;
    if (!with_topic(t, [](auto) {})) throw std::invalid_argument("unknown topic '" + t + "'");
    topics.push_back(t);
  }
  return topics;
}

}  // namespace hcosim::services::runtime

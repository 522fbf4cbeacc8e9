// hcosim security init: a test certificate authority, one certificate per
// participant, and governance and permissions documents signed by the CA,
// made with the openssl command (docs/security.md).
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <sstream>

#include "adapters/deployment.h"
#include "services/cli/cli.h"
#include "services/runtime/participant.h"

namespace fs = std::filesystem;

namespace hcosim::services::cli {
namespace {

// Runs openssl with `args`; throws with its own message when it fails.
void openssl(const std::vector<std::string>& args) {
  int out[2];
  if (pipe(out) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
  std::vector<char*> argv{const_cast<char*>("openssl")};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    dup2(out[1], STDOUT_FILENO);
    dup2(out[1], STDERR_FILENO);
    close(out[0]);
    close(out[1]);
    execvp("openssl", argv.data());
    _exit(127);
  }
  close(out[1]);
  std::string said;
  char buf[4096];
  for (ssize_t n; (n = read(out[0], buf, sizeof buf)) > 0;) said.append(buf, std::size_t(n));
  close(out[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  std::string cmd = "openssl";
  for (const auto& a : args) cmd += " " + a;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127)
    throw std::runtime_error("cannot run openssl (install the openssl package): " + cmd);
  throw std::runtime_error(cmd + " failed:\n" + said);
}

// ISO 8601 UTC, as the permissions document's validity wants it.
std::string utc(std::time_t t) {
  char s[32];
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::strftime(s, sizeof s, "%Y-%m-%dT%H:%M:%S", &tm);
  return s;
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream f(path);
  f << text;
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

// The same policy for every domain: only participants holding a
// certificate of this CA join, discovery and liveliness are encrypted
// (topic names stay hidden), and so is every sample's payload. `all` also
// encrypts every RTPS message and submessage (sequence numbers,
// heartbeats): in lockstep, whose writers heartbeat every
// kLockstepHeartbeatNs, that costs far more (docs/security.md measures it).
std::string governance(bool all) {
  const std::string whole = all ? "ENCRYPT" : "NONE";
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<!-- Made by hcosim security init (docs/security.md). -->
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>)" +
         std::to_string(adapters::kMaxDomain) + R"(</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>)" +
         whole + R"(</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>)" +
         whole + R"(</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)";
}

// One grant per identity: services and tools publish and subscribe to
// every topic; a reader only subscribes. Anything else is denied.
std::string permissions(const std::set<std::string>& full, const std::set<std::string>& readers,
                        const std::string& domains, const std::string& from, const std::string& until) {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- Made by hcosim security init (docs/security.md). -->\n"
    << "<dds xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\"\n"
    << "     "
       "xsi:noNamespaceSchemaLocation=\"http://www.omg.org/spec/DDS-SECURITY/20170901/"
       "omg_shared_ca_permissions.xsd\">\n"
    << "  <permissions>\n";
  auto grant = [&](const std::string& name, bool publish) {
    x << "    <grant name=\"" << name << "\">\n"
      << "      <subject_name>CN=" << name << "</subject_name>\n"
      << "      <validity><not_before>" << from << "</not_before><not_after>" << until << "</not_after></validity>\n"
      << "      <allow_rule>\n        <domains>" << domains << "</domains>\n";
    if (publish) x << "        <publish><topics><topic>*</topic></topics></publish>\n";
    x << "        <subscribe><topics><topic>*</topic></topics></subscribe>\n"
      << "      </allow_rule>\n      <default>DENY</default>\n    </grant>\n";
  };
  for (const auto& n : full) grant(n, true);
  for (const auto& n : readers) grant(n, false);
  x << "  </permissions>\n</dds>\n";
  return x.str();
}

std::set<std::string> names_in(const std::string& list, const char* flag) {
  static const std::regex valid("[A-Za-z0-9_]{1,63}");
  std::set<std::string> out;
  std::stringstream ss(list);
  for (std::string n; std::getline(ss, n, ',');) {
    if (n.empty()) continue;
    if (!std::regex_match(n, valid))
      throw std::invalid_argument(std::string(flag) + ": '" + n + "' is not a name ([A-Za-z0-9_], at most 63)");
    out.insert(n);
  }
  return out;
}

struct InitOptions {
  std::string dir, deployment, identities, readers, protection = "data";
  int days = 365;
  bool force = false, keep = false;
};

int init(const InitOptions& o) {
  adapters::Deployment d;
  if (!o.deployment.empty()) d = adapters::load_deployment(o.deployment);
  const std::string dir = o.dir.empty() ? d.security : o.dir;
  if (dir.empty())
    throw std::invalid_argument("security init needs a DIR, or a --deployment FILE with a 'security' section");
  const std::string& protection = o.protection;
  const int days = o.days;

  // Who gets a certificate: the tools, the lockstep clock, every service of
  // the deployment, and whoever is named.
  std::set<std::string> full = names_in(o.identities, "--identities");
  const std::set<std::string> readers = names_in(o.readers, "--readers");
  full.insert(runtime::kToolIdentity);
  if (!d.file.empty()) {
    full.insert("clock");
    for (const auto& s : d.services) full.insert(s.name);
  }
  for (const auto& r : readers)
    if (full.count(r)) throw std::invalid_argument("--readers: '" + r + "' is also a publishing identity");

  if (fs::exists(runtime::ca_file(dir))) {
    if (o.keep) {
      std::cout << "hcosim security: keeping the credentials in " << dir << "\n";
      return 0;
    }
    if (!o.force)
      throw std::invalid_argument(dir + " already holds a CA (" + runtime::ca_file(dir) +
                                  "); --force replaces everything in it, --keep keeps it, or choose another folder");
    for (const auto& f : {runtime::ca_file(dir), runtime::ca_key_file(dir), runtime::governance_file(dir),
                          runtime::permissions_file(dir)})
      fs::remove(f);
    fs::remove_all(fs::path(dir) / "identities");
  }
  fs::create_directories(fs::path(dir) / "identities");
  fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace);
  const std::string valid = std::to_string(days);

  // The CA: one key pair both for identities (PKI-DH) and for documents
  // (Access-Permissions). ECDSA P-256, which both plugins accept.
  std::cerr << "hcosim security: CA in " << dir << "\n";
  openssl({"genpkey", "-algorithm", "EC", "-pkeyopt", "ec_paramgen_curve:P-256", "-out", runtime::ca_key_file(dir)});
  fs::permissions(runtime::ca_key_file(dir), fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::replace);
  openssl({"req", "-x509", "-new", "-key", runtime::ca_key_file(dir), "-sha256", "-days", valid, "-subj",
           "/CN=hcosim test CA", "-out", runtime::ca_file(dir)});
  std::set<std::string> everyone = full;
  everyone.insert(readers.begin(), readers.end());
  for (const auto& n : everyone) {
    const std::string key = runtime::key_file(dir, n), cert = runtime::certificate_file(dir, n);
    const std::string csr = (fs::path(dir) / "identities" / (n + ".csr")).string();
    openssl({"genpkey", "-algorithm", "EC", "-pkeyopt", "ec_paramgen_curve:P-256", "-out", key});
    fs::permissions(key, fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::replace);
    openssl({"req", "-new", "-key", key, "-subj", "/CN=" + n, "-out", csr});
    openssl({"x509", "-req", "-in", csr, "-CA", runtime::ca_file(dir), "-CAkey", runtime::ca_key_file(dir),
             "-CAcreateserial", "-sha256", "-days", valid, "-out", cert});
    fs::remove(csr);
    std::cerr << "hcosim security: identity " << n << (readers.count(n) ? " (subscribe only)" : "") << "\n";
  }
  fs::remove(fs::path(dir) / "ca.srl");

  const std::time_t now = std::time(nullptr);
  const std::string domains =
      d.file.empty() ? "<id_range><min>0</min><max>" + std::to_string(adapters::kMaxDomain) + "</max></id_range>"
                     : "<id>" + std::to_string(d.domain) + "</id>";
  const fs::path gov = fs::path(dir) / "governance.xml", perm = fs::path(dir) / "permissions.xml";
  write(gov, governance(protection == "all"));
  write(perm, permissions(full, readers, domains, utc(now - 3600), utc(now + std::time_t(days) * 86400)));
  for (const auto& [xml, signed_] :
       {std::pair{gov.string(), runtime::governance_file(dir)}, {perm.string(), runtime::permissions_file(dir)}})
    openssl({"smime", "-sign", "-text", "-in", xml, "-signer", runtime::ca_file(dir), "-inkey",
             runtime::ca_key_file(dir), "-out", signed_});
  std::cout << "hcosim security: " << everyone.size() << " identities in " << dir << " (CA " << runtime::ca_file(dir)
            << ", valid " << valid << " days, " << protection << " encrypted"
            << (d.file.empty() ? "" : ", domain " + std::to_string(d.domain)) << ")\n";
  return 0;
}

}  // namespace

void add_security(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<InitOptions>();
  CLI::App* security = app.add_subcommand("security", "DDS Security credentials (docs/security.md)");
  security->require_subcommand(1);
  CLI::App* c = security->add_subcommand(
      "init",
      "make a test CA, a certificate per service of FILE (and for the tools, the clock and A, B; R may only "
      "subscribe) and signed governance and permissions documents in DIR, else FILE's security dir; a DIR that "
      "holds a CA is replaced with --force, kept with --keep; --protection all also encrypts every RTPS message, "
      "not only payloads and discovery");
  c->add_option("DIR", o->dir, "the folder to write (default: the deployment's security dir)");
  c->add_option("--deployment", o->deployment, "a certificate for each of its services, and its domain")
      ->option_text("FILE");
  c->add_option("--identities", o->identities, "more publishing identities, comma-separated")->option_text("A,B");
  c->add_option("--readers", o->readers, "subscribe-only identities, comma-separated")->option_text("R");
  c->add_option("--protection", o->protection, "what is encrypted (default data)")
      ->option_text("data|all")
      ->check(CLI::IsMember({"data", "all"}).description(""));
  c->add_option("--days", o->days, "validity, days (default 365)")->option_text("N")->check(CLI::Range(1, 36500));
  CLI::Option* force = c->add_flag("--force", o->force, "replace the credentials in DIR");
  c->add_flag("--keep", o->keep, "keep the credentials in DIR")->excludes(force);
  c->callback([&chosen, o] { chosen = [o] { return init(*o); }; });
}

}  // namespace hcosim::services::cli

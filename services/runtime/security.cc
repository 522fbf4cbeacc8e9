#include "services/runtime/security.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace hcosim::services::runtime {

namespace fs = std::filesystem;

std::string ca_file(const std::string& dir) { return (fs::path(dir) / "ca.pem").string(); }
std::string ca_key_file(const std::string& dir) { return (fs::path(dir) / "ca.key").string(); }
std::string governance_file(const std::string& dir) { return (fs::path(dir) / "governance.p7s").string(); }
std::string permissions_file(const std::string& dir) { return (fs::path(dir) / "permissions.p7s").string(); }
std::string certificate_file(const std::string& dir, const std::string& identity) {
  return (fs::path(dir) / "identities" / (identity + ".pem")).string();
}
std::string key_file(const std::string& dir, const std::string& identity) {
  return (fs::path(dir) / "identities" / (identity + ".key")).string();
}

void check_credentials(const Security& s) {
  for (const std::string& f : {ca_file(s.dir), governance_file(s.dir), permissions_file(s.dir),
                               certificate_file(s.dir, s.identity), key_file(s.dir, s.identity)})
    if (!std::ifstream(f))
      throw std::runtime_error("DDS Security: cannot read " + f + " (identity '" + s.identity +
                               "'); make the credentials with: hcosim security init " + s.dir +
                               " --deployment FILE (docs/security.md)");
}

void add_security(const Security& s, eprosima::fastdds::dds::DomainParticipantQos& qos) {
  if (!s.on()) return;
  check_credentials(s);
  // Fast DDS reads "file://" + path; an absolute path keeps it independent of the working directory.
  auto uri = [](const std::string& f) { return "file://" + fs::absolute(f).lexically_normal().string(); };
  auto& p = qos.properties().properties();
  p.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  p.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", uri(ca_file(s.dir)));
  p.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_certificate", uri(certificate_file(s.dir, s.identity)));
  p.emplace_back("dds.sec.auth.builtin.PKI-DH.private_key", uri(key_file(s.dir, s.identity)));
  p.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  p.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions_ca", uri(ca_file(s.dir)));
  p.emplace_back("dds.sec.access.builtin.Access-Permissions.governance", uri(governance_file(s.dir)));
  p.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions", uri(permissions_file(s.dir)));
  p.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

}  // namespace hcosim::services::runtime

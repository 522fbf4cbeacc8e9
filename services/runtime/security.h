// DDS Security for a participant: Fast DDS's built-in plugins, PKI-DH
// authentication, access control by signed governance and permissions
// documents, AES-GCM encryption (docs/security.md). The credentials are a
// folder that `hcosim security init` makes; its layout is fixed here.
#pragma once

#include <string>

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

namespace hcosim::services::runtime {

// Which credentials a participant joins with. `dir` empty: security off.
struct Security {
  std::string dir;       // credentials folder (hcosim security init DIR)
  std::string identity;  // certificate to present: DIR/identities/IDENTITY.pem
  bool on() const { return !dir.empty(); }
};

// The identity of hcosim's own tools (up, echo, record, ...).
inline constexpr const char* kToolIdentity = "hcosim";

// Files of a credentials folder.
std::string ca_file(const std::string& dir);           // CA certificate: identities and documents
std::string ca_key_file(const std::string& dir);       // CA private key (a test CA: docs/security.md)
std::string governance_file(const std::string& dir);   // signed governance (S/MIME)
std::string permissions_file(const std::string& dir);  // signed permissions, one grant per identity
std::string certificate_file(const std::string& dir, const std::string& identity);
std::string key_file(const std::string& dir, const std::string& identity);

// Throws std::runtime_error naming the first file of `s` that cannot be
// read, and the command that makes it.
void check_credentials(const Security& s);

// Turns the three plugins on in `qos` with the credentials of `s`
// (checked first). Nothing when security is off.
void add_security(const Security& s, eprosima::fastdds::dds::DomainParticipantQos& qos);

}  // namespace hcosim::services::runtime

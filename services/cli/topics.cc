// hcosim topics: every topic and type announced on a domain, ours or not,
// and where each writer and reader is: its participant, that
// participant's address, and with --deployment the host it names.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include <fastdds/dds/domain/DomainParticipantListener.hpp>

#include <fastrtps/utils/IPLocator.h>

#include "adapters/deployment.h"
#include "services/cli/cli.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {
namespace {

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::GuidPrefix_t;
using eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;
using eprosima::fastrtps::rtps::ReaderDiscoveryInfo;
using eprosima::fastrtps::rtps::RemoteLocatorList;
using eprosima::fastrtps::rtps::WriterDiscoveryInfo;

struct Entry {
  std::string type;
  int writers = 0;
  int readers = 0;
};

// A discovered participant: its name and the UDPv4 address it announced
// (the first not on loopback, else loopback). "" when Fast DDS kept only its
// shared-memory locators: it runs on this host.
struct Peer {
  std::string name;
  std::string address;
};

// One writer or reader, by its participant.
struct Endpoint {
  std::string topic;
  bool writer = false;
  GuidPrefix_t participant;
};

std::string address_of(const RemoteLocatorList& locators) {
  std::string loopback;
  for (const auto& l : locators.unicast) {
    if (l.kind != LOCATOR_KIND_UDPv4) continue;
    const std::string a = eprosima::fastrtps::rtps::IPLocator::ip_to_string(l);
    if (a.rfind("127.", 0) != 0) return a;
    if (loopback.empty()) loopback = a;
  }
  return loopback;
}

// Counts discovered writers and readers per topic, and keeps where each is.
class Discovery : public DomainParticipantListener {
 public:
  void on_participant_discovery(DomainParticipant*, ParticipantDiscoveryInfo&& info) override {
    if (info.status != ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT) return;
    std::string address = address_of(info.info.metatraffic_locators);
    if (address.empty()) address = address_of(info.info.default_locators);
    std::lock_guard<std::mutex> lock(mutex_);
    peers_[info.info.m_guid.guidPrefix] = {info.info.m_participantName.to_string(), address};
  }
  void on_publisher_discovery(DomainParticipant*, WriterDiscoveryInfo&& info) override {
    const int d = info.status == WriterDiscoveryInfo::DISCOVERED_WRITER ? 1
                  : info.status == WriterDiscoveryInfo::REMOVED_WRITER  ? -1
                                                                        : 0;
    std::lock_guard<std::mutex> lock(mutex_);
    Entry& e = topics_[info.info.topicName().to_string()];
    e.type = info.info.typeName().to_string();
    e.writers += d;
    if (d > 0) endpoints_.push_back({info.info.topicName().to_string(), true, info.info.guid().guidPrefix});
  }
  void on_subscriber_discovery(DomainParticipant*, ReaderDiscoveryInfo&& info) override {
    const int d = info.status == ReaderDiscoveryInfo::DISCOVERED_READER ? 1
                  : info.status == ReaderDiscoveryInfo::REMOVED_READER  ? -1
                                                                        : 0;
    std::lock_guard<std::mutex> lock(mutex_);
    Entry& e = topics_[info.info.topicName().to_string()];
    e.type = info.info.typeName().to_string();
    e.readers += d;
    if (d > 0) endpoints_.push_back({info.info.topicName().to_string(), false, info.info.guid().guidPrefix});
  }
  std::map<std::string, Entry> snapshot() {
    std::lock_guard<std::mutex> lock(mutex_);
    return topics_;
  }
  // One line per writer and reader, by topic: its participant, address and
  // host; `here` and `here_host` are this host's.
  std::vector<std::string> where(const std::map<std::string, std::string>& host_of, const std::string& here,
                                 const std::string& here_host) {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::string> lines;
    for (const Endpoint& e : endpoints_) {
      const auto p = peers_.find(e.participant);
      const Peer peer = p == peers_.end() ? Peer{"?", "?"} : p->second;
      const std::string address = peer.address.empty() ? here : peer.address;
      const auto h = host_of.find(address);
      const std::string host = peer.address.empty() ? here_host : h == host_of.end() ? "-" : h->second;
      char line[256];
      std::snprintf(line, sizeof line, "%-24s %-7s %-20s %-16s %s", e.topic.c_str(), e.writer ? "writer" : "reader",
                    peer.name.c_str(), address.c_str(), host.c_str());
      lines.push_back(line);
    }
    std::sort(lines.begin(), lines.end());
    return lines;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, Entry> topics_;
  std::map<GuidPrefix_t, Peer> peers_;
  std::vector<Endpoint> endpoints_;  // as discovered (a removed one stays listed)
};

struct TopicsOptions {
  double wait_s = 2;
  std::string deployment;  // its hosts name the addresses
  std::string host;        // join as a process of this host of the deployment does
  runtime::DdsOptions dds;
};

int topics(const TopicsOptions& o) {
  const double wait = o.wait_s;
  std::map<std::string, std::string> host_of;  // address -> host
  runtime::Network network;
  if (!o.deployment.empty()) {
    const adapters::Deployment d = adapters::load_deployment(o.deployment);
    for (const adapters::Host& h : d.hosts)
      if (!h.address.empty()) host_of[h.address] = h.name;
    if (!o.host.empty()) {
      adapters::services_on(d, o.host);  // a host the file lacks is refused
      network = runtime::network_of(d, o.host);
    }
  } else if (!o.host.empty()) {
    throw std::invalid_argument("--host needs --deployment: the file that names the hosts");
  }
  Discovery discovery;
  {
    runtime::Participant p(o.dds.domain, "hcosim_topics", runtime::default_qos_file(), &discovery, false,
                           o.dds.security, network);
    std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    p.dds()->set_listener(nullptr);
  }
  const auto topics = discovery.snapshot();
  std::printf("%-24s %-28s %7s %7s\n", "TOPIC", "TYPE", "WRITERS", "READERS");
  for (const auto& [name, e] : topics)
    std::printf("%-24s %-28s %7d %7d\n", name.c_str(), e.type.c_str(), e.writers, e.readers);
  if (topics.empty()) {
    std::printf("(no topics seen on domain %d within %.1f s)\n", o.dds.domain, wait);
    return 0;
  }
  std::printf("\n%-24s %-7s %-20s %-16s %s\n", "TOPIC", "ENDS", "PARTICIPANT", "ADDRESS", "HOST");
  const std::string here = network.address.empty() ? "(this host)" : network.address;
  for (const std::string& line : discovery.where(host_of, here, o.host.empty() ? "-" : o.host))
    std::printf("%s\n", line.c_str());
  return 0;
}

}  // namespace

void add_topics(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<TopicsOptions>();
  CLI::App* c = app.add_subcommand(
      "topics", "list the topics and types seen on a domain, and each writer's and reader's participant and host");
  c->add_option("--wait", o->wait_s, "listen for S seconds (default 2)")
      ->option_text("S")
      ->check(runtime::within(0.001, 600));
  c->add_option("--deployment", o->deployment, "name each address by the file's hosts (docs/deployment.md)")
      ->option_text("FILE");
  c->add_option("--host", o->host, "join the rig's network as a process of host NAME of the file does")
      ->option_text("NAME");
  runtime::add_dds(*c, o->dds);
  c->callback([&chosen, o] { chosen = [o] { return topics(*o); }; });
}

}  // namespace hcosim::services::cli

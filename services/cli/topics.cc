// hcosim topics: every topic and type announced on a domain, ours or not.
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>

#include <fastdds/dds/domain/DomainParticipantListener.hpp>

#include "services/cli/cli.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {
namespace {

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::ReaderDiscoveryInfo;
using eprosima::fastrtps::rtps::WriterDiscoveryInfo;

struct Entry {
  std::string type;
  int writers = 0;
  int readers = 0;
};

// Counts discovered writers and readers per topic.
class Discovery : public DomainParticipantListener {
 public:
  void on_publisher_discovery(DomainParticipant*, WriterDiscoveryInfo&& info) override {
    const int d = info.status == WriterDiscoveryInfo::DISCOVERED_WRITER ? 1
                  : info.status == WriterDiscoveryInfo::REMOVED_WRITER  ? -1
                                                                        : 0;
    std::lock_guard<std::mutex> lock(mutex_);
    Entry& e = topics_[info.info.topicName().to_string()];
    e.type = info.info.typeName().to_string();
    e.writers += d;
  }
  void on_subscriber_discovery(DomainParticipant*, ReaderDiscoveryInfo&& info) override {
    const int d = info.status == ReaderDiscoveryInfo::DISCOVERED_READER ? 1
                  : info.status == ReaderDiscoveryInfo::REMOVED_READER  ? -1
                                                                        : 0;
    std::lock_guard<std::mutex> lock(mutex_);
    Entry& e = topics_[info.info.topicName().to_string()];
    e.type = info.info.typeName().to_string();
    e.readers += d;
  }
  std::map<std::string, Entry> snapshot() {
    std::lock_guard<std::mutex> lock(mutex_);
    return topics_;
  }

 private:
  std::mutex mutex_;
  std::map<std::string, Entry> topics_;
};

}  // namespace

int topics(const std::vector<std::string>& argv) {
  const Args a = parse(argv, {"--domain", "--security", "--identity", "--wait"}, {});
  if (!a.positional.empty()) throw std::invalid_argument("topics takes no positional argument");
  const double wait = a.number("--wait", 2.0);
  if (wait <= 0 || wait > 600) throw std::invalid_argument("--wait must be in (0, 600] s");
  Discovery discovery;
  {
    runtime::Participant p(domain_of(a), "hcosim_topics", runtime::default_qos_file(), &discovery, false,
                           security_of(a));
    std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    p.dds()->set_listener(nullptr);
  }
  const auto topics = discovery.snapshot();
  std::printf("%-24s %-28s %7s %7s\n", "TOPIC", "TYPE", "WRITERS", "READERS");
  for (const auto& [name, e] : topics)
    std::printf("%-24s %-28s %7d %7d\n", name.c_str(), e.type.c_str(), e.writers, e.readers);
  if (topics.empty()) std::printf("(no topics seen on domain %d within %.1f s)\n", domain_of(a), wait);
  return 0;
}

}  // namespace hcosim::services::cli

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

struct TopicsOptions {
  double wait_s = 2;
  runtime::DdsOptions dds;
};

int topics(const TopicsOptions& o) {
  const double wait = o.wait_s;
  Discovery discovery;
  {
    runtime::Participant p(o.dds.domain, "hcosim_topics", runtime::default_qos_file(), &discovery, false,
                           o.dds.security);
    std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    p.dds()->set_listener(nullptr);
  }
  const auto topics = discovery.snapshot();
  std::printf("%-24s %-28s %7s %7s\n", "TOPIC", "TYPE", "WRITERS", "READERS");
  for (const auto& [name, e] : topics)
    std::printf("%-24s %-28s %7d %7d\n", name.c_str(), e.type.c_str(), e.writers, e.readers);
  if (topics.empty()) std::printf("(no topics seen on domain %d within %.1f s)\n", o.dds.domain, wait);
  return 0;
}

}  // namespace

void add_topics(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<TopicsOptions>();
  CLI::App* c = app.add_subcommand("topics", "list the topics and types seen on a domain");
  c->add_option("--wait", o->wait_s, "listen for S seconds (default 2)")
      ->option_text("S")
      ->check(runtime::within(0.001, 600));
  runtime::add_dds(*c, o->dds);
  c->callback([&chosen, o] { chosen = [o] { return topics(*o); }; });
}

}  // namespace hcosim::services::cli

// hcosim echo and hcosim hz: watch one topic of the contract.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "adapters/idl_json.h"
#include "services/cli/cli.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {
namespace {

// What echo and hz were asked.
struct TopicOptions {
  std::string topic;
  double count = 0, timeout_s = 0, duration_s = 0;
  runtime::DdsOptions dds;
};

// Calls f(TypeTag) for the topic's type (checked by the command line).
template <class F>
int for_topic(const std::string& topic, F&& f) {
  int code = 0;
  runtime::with_topic(topic, [&](auto tag) { code = f(tag); });
  return code;
}

int echo(const TopicOptions& o) {
  const double count = o.count, timeout = o.timeout_s;
  return for_topic(o.topic, [&](auto tag) {
    using T = typename decltype(tag)::type;
    runtime::install_stop_handlers();
    runtime::Participant p(o.dds.domain, "hcosim_echo", runtime::default_qos_file(), nullptr, false, o.dds.security);
    // No validation: echo shows what is on the wire, bad samples included.
    runtime::Reader<T> reader(p, nullptr, nullptr, runtime::TopicOf<T>::qos, runtime::kMonitorDepth);
    const std::int64_t deadline = timeout > 0 ? runtime::mono_ns() + std::int64_t(timeout * 1e9) : INT64_MAX;
    std::uint64_t seen = 0;
    while (!runtime::stop_requested() && (count == 0 || seen < count) && runtime::mono_ns() < deadline) {
      if (!reader.wait(std::chrono::milliseconds(100))) continue;
      reader.take([&](const T& s) {
        if (count > 0 && seen >= count) return;
        std::fputs(adapters::to_json(s).c_str(), stdout);
        std::fputc('\n', stdout);
        ++seen;
      });
      std::fflush(stdout);
    }
    if (count > 0 && seen < count && !runtime::stop_requested()) {
      std::cerr << "hcosim echo: " << seen << " of " << count << " samples of " << o.topic << " on domain "
                << o.dds.domain << " within " << timeout << " s\n";
      return 1;
    }
    return 0;
  });
}

int hz(const TopicOptions& o) {
  const double duration = o.duration_s;
  return for_topic(o.topic, [&](auto tag) {
    using T = typename decltype(tag)::type;
    runtime::install_stop_handlers();
    runtime::Participant p(o.dds.domain, "hcosim_hz", runtime::default_qos_file(), nullptr, false, o.dds.security);
    runtime::Reader<T> reader(p, nullptr, nullptr, runtime::TopicOf<T>::qos, runtime::kMonitorDepth);
    const std::int64_t start = runtime::mono_ns();
    const std::int64_t end = duration > 0 ? start + std::int64_t(duration * 1e9) : INT64_MAX;
    runtime::Window periods_ms(1 << 16);
    std::uint64_t total = 0;
    std::int64_t first = 0, last = 0, next_report = start + 1'000'000'000;
    auto report = [&] {
      if (total < 2) {
        std::printf("%s: %llu samples\n", o.topic.c_str(), static_cast<unsigned long long>(total));
      } else {
        const double rate = double(total - 1) * 1e9 / double(last - first);
        std::printf("%s: %.2f Hz over %llu samples, period p50 %.3f ms p99 %.3f ms max %.3f ms\n", o.topic.c_str(),
                    rate, static_cast<unsigned long long>(total), periods_ms.percentile(0.5),
                    periods_ms.percentile(0.99), periods_ms.percentile(1.0));
      }
      std::fflush(stdout);
    };
    while (!runtime::stop_requested() && runtime::mono_ns() < end) {
      if (reader.wait(std::chrono::milliseconds(50)))
        reader.take([&](const T&) {
          const std::int64_t now = runtime::mono_ns();
          if (total == 0)
            first = now;
          else
            periods_ms.add((now - last) * 1e-6);
          last = now;
          ++total;
        });
      if (duration == 0 && runtime::mono_ns() >= next_report) {
        report();
        next_report += 1'000'000'000;
      }
    }
    report();
    return total >= 2 ? 0 : 1;
  });
}

}  // namespace

void add_echo(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<TopicOptions>();
  CLI::App* c = app.add_subcommand("echo", "print samples of one of hcosim's topics as JSON lines");
  c->add_option("TOPIC", o->topic, "topic name (docs/topics.md)")->required()->check(runtime::topic_name());
  c->add_option("--count", o->count, "stop after N samples (0: until Ctrl-C); fewer within --timeout fail")
      ->option_text("N")
      ->check(runtime::within(0, 1e12));
  c->add_option("--timeout", o->timeout_s, "give up after S seconds (0: never)")
      ->option_text("S")
      ->check(runtime::within(0, 1e9));
  runtime::add_dds(*c, o->dds);
  c->callback([&chosen, o] { chosen = [o] { return echo(*o); }; });
}

void add_hz(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<TopicOptions>();
  CLI::App* c = app.add_subcommand("hz", "measure the rate at which a topic's samples arrive");
  c->add_option("TOPIC", o->topic, "topic name (docs/topics.md)")->required()->check(runtime::topic_name());
  c->add_option("--duration", o->duration_s, "measure for S seconds (0: report each second until Ctrl-C)")
      ->option_text("S")
      ->check(runtime::within(0, 1e9));
  runtime::add_dds(*c, o->dds);
  c->callback([&chosen, o] { chosen = [o] { return hz(*o); }; });
}

}  // namespace hcosim::services::cli

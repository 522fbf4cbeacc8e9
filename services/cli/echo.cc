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

std::string known_topics() {
  std::string out;
  runtime::for_each_topic([&](auto tag) {
    out += (out.empty() ? "" : ", ") + std::string(runtime::TopicOf<typename decltype(tag)::type>::name);
  });
  return out;
}

// Calls f(TypeTag) for the topic named by the single positional argument.
template <class F>
int for_topic(const Args& a, const char* cmd, F&& f) {
  if (a.positional.size() != 1) throw std::invalid_argument(std::string(cmd) + " needs exactly one TOPIC");
  int code = 0;
  if (!runtime::with_topic(a.positional[0], [&](auto tag) { code = f(tag); }))
    throw std::invalid_argument("unknown topic '" + a.positional[0] + "' (known: " + known_topics() + ")");
  return code;
}

}  // namespace

int echo(const std::vector<std::string>& argv) {
  const Args a = parse(argv, {"--count", "--timeout", "--domain", "--security", "--identity"}, {});
  const double count = a.number("--count", 0);
  const double timeout = a.number("--timeout", 0);
  if (count < 0 || timeout < 0) throw std::invalid_argument("--count and --timeout must not be negative");
  return for_topic(a, "echo", [&](auto tag) {
    using T = typename decltype(tag)::type;
    runtime::install_stop_handlers();
    runtime::Participant p(domain_of(a), "hcosim_echo", runtime::default_qos_file(), nullptr, false, security_of(a));
    // No validation: echo shows what is on the wire, bad samples included.
    runtime::Reader<T> reader(p);
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
      std::cerr << "hcosim echo: " << seen << " of " << count << " samples of " << a.positional[0] << " on domain "
                << domain_of(a) << " within " << timeout << " s\n";
      return 1;
    }
    return 0;
  });
}

int hz(const std::vector<std::string>& argv) {
  const Args a = parse(argv, {"--duration", "--domain", "--security", "--identity"}, {});
  const double duration = a.number("--duration", 0);
  if (duration < 0) throw std::invalid_argument("--duration must not be negative");
  return for_topic(a, "hz", [&](auto tag) {
    using T = typename decltype(tag)::type;
    runtime::install_stop_handlers();
    runtime::Participant p(domain_of(a), "hcosim_hz", runtime::default_qos_file(), nullptr, false, security_of(a));
    runtime::Reader<T> reader(p);
    const std::int64_t start = runtime::mono_ns();
    const std::int64_t end = duration > 0 ? start + std::int64_t(duration * 1e9) : INT64_MAX;
    runtime::Window periods_ms(1 << 16);
    std::uint64_t total = 0;
    std::int64_t first = 0, last = 0, next_report = start + 1'000'000'000;
    auto report = [&] {
      if (total < 2) {
        std::printf("%s: %llu samples\n", a.positional[0].c_str(), static_cast<unsigned long long>(total));
      } else {
        const double rate = double(total - 1) * 1e9 / double(last - first);
        std::printf("%s: %.2f Hz over %llu samples, period p50 %.3f ms p99 %.3f ms max %.3f ms\n",
                    a.positional[0].c_str(), rate, static_cast<unsigned long long>(total), periods_ms.percentile(0.5),
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

}  // namespace hcosim::services::cli

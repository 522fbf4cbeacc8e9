// hcosim record: topics into a recording (docs/recording.md), or a haptic
// device's HapticState as a CSV trajectory that the replay backend plays
// back (adapters/device/replay.h).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "services/cli/cli.h"
#include "services/runtime/recording.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {

namespace {

// hcosim record FILE: every sample of the chosen topics (all by default)
// into a recording (docs/recording.md).
int record_topics(const Args& a) {
  if (a.positional.size() != 1 || a.has("--out") || a.has("--device"))
    throw std::invalid_argument("usage: hcosim record FILE [--topics T1,T2] [--duration S] [--domain D]");
  const std::vector<std::string> topics = topics_of(a);
  const double duration = a.number("--duration", 0);
  if (duration < 0) throw std::invalid_argument("--duration must not be negative");
  runtime::install_stop_handlers();
  runtime::Participant p(domain_of(a), "hcosim_record", runtime::default_qos_file(), nullptr, false, security_of(a));
  runtime::Recorder recorder(p, a.positional[0], topics);
  const std::int64_t end = duration > 0 ? runtime::mono_ns() + std::int64_t(duration * 1e9) : INT64_MAX;
  while (!runtime::stop_requested() && runtime::mono_ns() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  recorder.close();
  std::cerr << "hcosim record: " << recorder.samples() << " samples to " << a.positional[0] << "\n";
  if (const std::string lost = recorder.losses(); !lost.empty())
    std::cerr << "hcosim record: samples Fast DDS reports the recording never received: " << lost << "\n";
  return 0;
}

}  // namespace

int record(const std::vector<std::string>& argv) {
  const Args a =
      parse(argv, {"--out", "--device", "--duration", "--domain", "--security", "--identity", "--topics"}, {});
  if (!a.positional.empty()) return record_topics(a);
  const std::string out = a.get("--out", "");
  if (out.empty())
    throw std::invalid_argument("record needs FILE (a recording) or --out FILE.csv (a haptic trajectory)");
  const std::string device = a.get("--device", "");
  const double duration = a.number("--duration", 0);
  if (duration < 0) throw std::invalid_argument("--duration must not be negative");
  std::ofstream csv(out);
  if (!csv) throw std::runtime_error(out + ": cannot be written");
  csv.precision(9);
  csv << "time_s,x,y,z,buttons\n";
  runtime::install_stop_handlers();
  runtime::Participant p(domain_of(a), "hcosim_record", runtime::default_qos_file(), nullptr, false, security_of(a));
  runtime::Reader<HapticState> reader(p, [](const HapticState& s) { return adapters::validate(s); });
  const std::int64_t end = duration > 0 ? runtime::mono_ns() + std::int64_t(duration * 1e9) : INT64_MAX;
  std::uint64_t n = 0;
  double last = -1;
  while (!runtime::stop_requested() && runtime::mono_ns() < end) {
    if (!reader.wait(std::chrono::milliseconds(100))) continue;
    reader.take([&](const HapticState& s) {
      if (!device.empty() && s.device().to_string() != device) return;
      if (s.device_time_s() <= last) return;  // replay needs increasing times
      last = s.device_time_s();
      csv << s.device_time_s() << ',' << s.position().x() << ',' << s.position().y() << ',' << s.position().z() << ','
          << s.buttons() << '\n';
      ++n;
    });
  }
  csv.flush();
  if (!csv) throw std::runtime_error(out + ": write failed");
  std::cerr << "hcosim record: " << n << " samples to " << out << "\n";
  return n > 0 ? 0 : 1;
}

}  // namespace hcosim::services::cli

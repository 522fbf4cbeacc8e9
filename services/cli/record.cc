// hcosim record: topics into a recording (docs/recording.md: hcosim's own
// format or MCAP), or a haptic device's HapticState as a CSV trajectory
// that the replay backend plays back (adapters/device/replay.h).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "services/cli/cli.h"
#include "services/foxglove/panels.h"
#include "services/recording/recording.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {

namespace {

struct RecordOptions {
  std::string file;                 // a recording, or
  std::string out, device;          // a CSV trajectory of one device (all: "")
  std::vector<std::string> topics;  // none: every topic
  std::string format;               // hcosim or mcap; empty: by the file's name
  std::string compression = "zstd";
  std::string deployment;  // its scene's objects for the scene channels
  bool scene = true;       // MCAP: Foxglove's scene channels beside the topics
  double duration_s = 0;
  runtime::DdsOptions dds;
};

// hcosim record FILE: every sample of the chosen topics (all by default)
// into a recording (docs/recording.md).
int record_topics(const RecordOptions& o) {
  const std::vector<std::string>& topics = o.topics;
  const double duration = o.duration_s;
  runtime::install_stop_handlers();
  runtime::Participant p(o.dds.domain, "hcosim_record", runtime::default_qos_file(), nullptr, false, o.dds.security);
  const recording::RecordingFormat format =
      o.format.empty() ? recording::format_of(o.file) : recording::parse_recording_format(o.format);
  recording::Derive derive;
  if (o.scene && format == recording::RecordingFormat::mcap) {
    std::vector<adapters::foxglove::Item> items;
    adapters::foxglove::Options scene;
    if (!o.deployment.empty()) {
      const adapters::Deployment d = adapters::load_deployment(o.deployment);
      items = foxglove::panel_items(d), scene.tag_id = d.scene.marker.id.value_or(scene.tag_id);
    }
    derive = foxglove::panel_channels(std::move(items), scene);
  }
  recording::Recorder recorder(p, o.file, topics, format, recording::parse_compression(o.compression), derive);
  const std::int64_t end = duration > 0 ? runtime::mono_ns() + std::int64_t(duration * 1e9) : INT64_MAX;
  while (!runtime::stop_requested() && runtime::mono_ns() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  recorder.close();
  std::cerr << "hcosim record: " << recorder.samples() << " samples to " << o.file;
  if (recorder.derived()) std::cerr << ", and " << recorder.derived() << " scene messages for Foxglove";
  std::cerr << "\n";
  if (const std::string lost = recorder.losses(); !lost.empty())
    std::cerr << "hcosim record: samples Fast DDS reports the recording never received: " << lost << "\n";
  if (const std::string dropped = recorder.dropped(); !dropped.empty())
    std::cerr << "hcosim record: samples dropped because the recording's file fell "
              << (recording::Recorder::kQueueBytes >> 20) << " MiB behind: " << dropped << "\n";
  return 0;
}

// hcosim record --out FILE.csv: one device's stylus trajectory.
int record_trajectory(const RecordOptions& o) {
  const std::string &out = o.out, &device = o.device;
  const double duration = o.duration_s;
  std::ofstream csv(out);
  if (!csv) throw std::runtime_error(out + ": cannot be written");
  csv.precision(9);
  csv << "time_s,x,y,z,buttons\n";
  runtime::install_stop_handlers();
  runtime::Participant p(o.dds.domain, "hcosim_record", runtime::default_qos_file(), nullptr, false, o.dds.security);
  runtime::Reader<HapticState> reader(
      p, [](const HapticState& s) { return adapters::validate(s); }, nullptr, runtime::TopicOf<HapticState>::qos,
      runtime::kMonitorDepth);
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

}  // namespace

void add_record(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<RecordOptions>();
  CLI::App* c = app.add_subcommand("record",
                                   "record topics (all by default) into a recording REC (docs/recording.md), or with "
                                   "--out write a haptic device's HapticState as a trajectory the replay device plays");
  CLI::Option* file = c->add_option("REC", o->file, "the recording to write");
  runtime::add_topic_list(*c, o->topics);
  c->add_option("--format", o->format, "hcosim or mcap (default: mcap for a name ending in .mcap, else hcosim)")
      ->option_text("hcosim|mcap")
      ->check(CLI::IsMember({"hcosim", "mcap"}).description(""))
      ->needs(file);
  c->add_option("--compression", o->compression, "MCAP's chunks: zstd (default), lz4 or none")
      ->option_text("zstd|lz4|none")
      ->check(CLI::IsMember({"zstd", "lz4", "none"}).description(""))
      ->needs(file);
  c->add_option("--deployment", o->deployment,
                "MCAP: draw the scene's objects of this deployment in the scene channels (rigid bodies need their "
                "size; docs/foxglove.md)")
      ->option_text("FILE")
      ->check(CLI::ExistingFile)
      ->needs(file);
  c->add_flag(
       "--no-scene", [o](std::int64_t) { o->scene = false; }, "MCAP: no Foxglove scene channels")
      ->needs(file);
  c->add_option("--duration", o->duration_s, "record for S seconds (0: until Ctrl-C)")
      ->option_text("S")
      ->check(runtime::within(0, 1e9));
  runtime::add_dds(*c, o->dds);
  CLI::Option* out = c->add_option("--out", o->out, "the trajectory to write, CSV")->option_text("FILE.csv");
  c->add_option("--device", o->device, "the device whose trajectory to write (default: any)")
      ->option_text("NAME")
      ->needs(out);
  file->excludes(out);
  c->callback([&chosen, o] {
    if (o->file.empty() && o->out.empty())
      throw CLI::ValidationError("record needs REC (a recording) or --out FILE.csv (a haptic trajectory)");
    chosen = [o] { return o->out.empty() ? record_topics(*o) : record_trajectory(*o); };
  });
}

}  // namespace hcosim::services::cli

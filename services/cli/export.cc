// hcosim export: one topic of a recording, one sample a line, in step
// order. hcosim replay: a recording's samples published again, on the
// schedule they were recorded at.
#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <thread>
#include <tuple>

#include "adapters/idl_json.h"
#include "services/cli/cli.h"
#include "services/recording/recording.h"
#include "services/runtime/service.h"

namespace hcosim::services::cli {
namespace {

// The scalars of a decoded sample's JSON as (path, text) pairs:
// "stamp.step", "positions.3"; null (a non-finite number) is an empty cell.
void flatten(const adapters::Json& n, const std::string& path, std::vector<std::pair<std::string, std::string>>& out) {
  if (n.is_object()) {
    for (const auto& [k, v] : n.items()) flatten(v, path.empty() ? k : path + "." + k, out);
  } else if (n.is_array()) {
    for (std::size_t i = 0; i < n.size(); ++i) flatten(n[i], path + "." + std::to_string(i), out);
  } else {
    out.emplace_back(path, n.is_null() ? "" : n.is_string() ? n.get<std::string>() : n.dump());
  }
}

// Removes every "wall_time_ns" (it differs between runs of the same deployment).
void drop_wall_times(adapters::Json& n) {
  if (n.is_object()) {
    n.erase("wall_time_ns");
    for (auto& [k, v] : n.items()) drop_wall_times(v);
  } else if (n.is_array()) {
    for (auto& v : n) drop_wall_times(v);
  }
}

// A sample's instance key as Fast DDS hashes it (all zero on a topic
// without key fields).
using Key = std::array<std::uint8_t, 16>;
Key key_of(const recording::Record& r) {
  Key k{};
  runtime::with_topic(r.topic, [&](auto tag) {
    using T = typename decltype(tag)::type;
    T s = recording::from_cdr<T>(r.cdr);
    // A type support of its own, not recording::type_support's: getKey keeps
    // state in it (its key buffer and MD5), and a shared one gave every
    // sample after the first the same key, so one step's samples kept their
    // arrival order (integration.mcap saw two runs' ForceFeedback differ so).
    typename runtime::TopicOf<T>::PubSub type;
    eprosima::fastrtps::rtps::InstanceHandle_t h;
    if (type.m_isGetKeyDefined && type.getKey(&s, &h, false))
      for (std::size_t i = 0; i < k.size(); ++i) k[i] = h.value[i];
  });
  return k;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

struct ExportOptions {
  std::string file, topic, format = "jsonl";
  bool wall = false;
};

int export_recording(const ExportOptions& o) {
  const std::string &topic = o.topic, &format = o.format;
  recording::RecordingReader in(o.file);
  std::vector<recording::Record> records;
  std::vector<Key> keys;
  std::uint64_t total = 0;
  for (recording::Record r; in.next(r); ++total)
    if (r.topic == topic) {
      keys.push_back(key_of(r));
      records.push_back(std::move(r));
    }
  // Step order, then instance key: the same samples export the same lines
  // whatever order they arrived in (one step's meshes of several objects,
  // two lockstep runs). One instance's samples of a step keep their order.
  std::vector<std::size_t> order(records.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
    return std::tie(records[x].step, keys[x]) < std::tie(records[y].step, keys[y]);
  });
  std::vector<std::string> header;
  for (const std::size_t i : order) {
    const recording::Record& r = records[i];
    adapters::Json sample;
    runtime::with_topic(topic, [&](auto tag) {
      using T = typename decltype(tag)::type;
      sample = adapters::json_of(recording::from_cdr<T>(r.cdr));
    });
    if (!o.wall) drop_wall_times(sample);
    if (format == "jsonl") {
      std::printf("%s\n", adapters::json_line(sample).c_str());
      continue;
    }
    std::vector<std::pair<std::string, std::string>> cells;
    flatten(sample, "", cells);
    if (header.empty()) {
      std::string h;
      for (const auto& c : cells) header.push_back(c.first), h += (h.empty() ? "" : ",") + csv_field(c.first);
      std::printf("%s\n", h.c_str());
    }
    std::string row;
    for (std::size_t c = 0; c < cells.size(); ++c) row += (c ? "," : "") + csv_field(cells[c].second);
    std::printf("%s\n", row.c_str());
  }
  std::cerr << "hcosim export: " << records.size() << " " << topic << " samples of " << total << " in " << o.file
            << "\n";
  if (in.skipped())
    std::cerr << "hcosim export: " << in.skipped() << " messages of MCAP channels that carry no hcosim topic in CDR "
              << "skipped\n";
  return 0;
}

struct ReplayOptions {
  std::string file;
  std::vector<std::string> topics;  // none: every topic
  double speed = 1, wait_s = 10;
  std::string clock = "sim";
  runtime::DdsOptions dds;
};

int replay(const ReplayOptions& o) {
  const double wait_s = o.wait_s;
  const std::string& clock = o.clock;
  // The schedule: simulated time (a lockstep run plays back at its own
  // pace, not the pace its machine ran it at), or the receive times.
  const auto at = [&](const recording::Record& r) { return clock == "sim" ? r.sim_time_ns : r.receive_ns; };
  const double speed = o.speed;
  const std::vector<std::string>& topics = o.topics;
  recording::RecordingReader in(o.file);
  std::vector<recording::Record> records;
  for (recording::Record r; in.next(r);)
    if (topics.empty() || std::find(topics.begin(), topics.end(), r.topic) != topics.end())
      records.push_back(std::move(r));
  if (in.skipped())
    std::cerr << "hcosim replay: " << in.skipped() << " messages of MCAP channels that carry no hcosim topic in CDR "
              << "skipped\n";
  if (records.empty()) throw std::runtime_error(o.file + ": no sample of the chosen topics");
  std::stable_sort(records.begin(), records.end(),
                   [&](const recording::Record& x, const recording::Record& y) { return at(x) < at(y); });

  runtime::install_stop_handlers();
  runtime::Participant p(o.dds.domain, "hcosim_replay", runtime::default_qos_file(), nullptr, false, o.dds.security);
  // One writer per topic, made before the first sample so readers can match.
  std::map<std::string, std::function<void(const recording::Record&)>> write;
  std::map<std::string, std::function<int()>> matched;
  for (const recording::Record& r : records) {
    if (write.count(r.topic)) continue;
    runtime::with_topic(r.topic, [&](auto tag) {
      using T = typename decltype(tag)::type;
      auto w = std::make_shared<runtime::Writer<T>>(p);
      write[r.topic] = [w](const recording::Record& rec) {
        T s = recording::from_cdr<T>(rec.cdr);
        w->write(s);
      };
      matched[r.topic] = [w] { return w->matched(); };
    });
  }
  // A replay is for its subscribers: wait until every topic has one (a
  // service may still be building its model), up to --wait seconds.
  const std::int64_t give_up = runtime::mono_ns() + std::int64_t(wait_s * 1e9);
  std::string unread;
  do {
    unread.clear();
    for (const auto& [topic, count] : matched)
      if (count() == 0) unread += (unread.empty() ? "" : ", ") + topic;
    if (!unread.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  } while (!unread.empty() && runtime::mono_ns() < give_up && !runtime::stop_requested());
  if (!unread.empty())
    std::cerr << "hcosim replay: no reader of " << unread << " after " << wait_s << " s; replaying anyway\n";
  std::cerr << "hcosim replay: " << records.size() << " samples over "
            << (at(records.back()) - at(records.front())) * 1e-9 / speed << " s" << std::endl;
  const std::int64_t start = runtime::mono_ns(), first = at(records.front());
  std::uint64_t sent = 0;
  for (const recording::Record& r : records) {
    if (runtime::stop_requested()) break;
    const std::int64_t due = start + std::int64_t(double(at(r) - first) / speed);
    if (const std::int64_t wait = due - runtime::mono_ns(); wait > 0)
      std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
    write[r.topic](r);
    ++sent;
  }
  std::cerr << "hcosim replay: published " << sent << " samples" << std::endl;
  return 0;
}

}  // namespace

void add_export(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* c = app.add_subcommand("export", "print one topic of a recording, one sample a line, in step order");
  c->add_option("REC", o->file, "the recording")->required();
  c->add_option("--topic", o->topic, "the topic to print")
      ->option_text("TOPIC")
      ->required()
      ->check(runtime::topic_name());
  c->add_option("--format", o->format, "JSON lines (default) or CSV, one column per field")
      ->option_text("jsonl|csv")
      ->check(CLI::IsMember({"jsonl", "csv"}).description(""));
  c->add_flag("--wall", o->wall, "keep the wall-clock times, which differ from run to run");
  c->callback([&chosen, o] { chosen = [o] { return export_recording(*o); }; });
}

void add_replay(CLI::App& app, Command& chosen) {
  auto o = std::make_shared<ReplayOptions>();
  CLI::App* c = app.add_subcommand("replay",
                                   "publish a recording's samples again on their simulated-time schedule (or the one "
                                   "they were received on)");
  c->add_option("REC", o->file, "the recording")->required();
  runtime::add_topic_list(*c, o->topics);
  c->add_option("--speed", o->speed, "play X times as fast (default 1)")
      ->option_text("X")
      ->check(runtime::within(1e-6, 1000));
  c->add_option("--clock", o->clock, "schedule by simulated time (default) or by receive time")
      ->option_text("sim|receive")
      ->check(CLI::IsMember({"sim", "receive"}).description(""));
  c->add_option("--wait", o->wait_s, "wait up to S seconds for a reader of every topic (default 10)")
      ->option_text("S")
      ->check(runtime::within(0, 3600));
  runtime::add_dds(*c, o->dds);
  c->callback([&chosen, o] { chosen = [o] { return replay(*o); }; });
}

}  // namespace hcosim::services::cli

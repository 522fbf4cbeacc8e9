// hcosim export: one topic of a recording, one sample a line, in step order.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <regex>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "cli.h"
#include "idl_json.h"
#include "recording.h"
#include "service.h"

namespace hcosim::cli {
namespace {

// The scalars of a JSON object as (path, text) pairs: "stamp.step",
// "positions.3". JSON is YAML's flow style, so yaml-cpp reads it.
void flatten(const YAML::Node& n, const std::string& path, std::vector<std::pair<std::string, std::string>>& out) {
  if (n.IsMap()) {
    for (const auto& kv : n) flatten(kv.second, path.empty() ? kv.first.Scalar() : path + "." + kv.first.Scalar(), out);
  } else if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i) flatten(n[i], path + "." + std::to_string(i), out);
  } else {
    out.emplace_back(path, n.IsNull() ? "" : n.Scalar());
  }
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

int export_recording(const std::vector<std::string>& argv) {
  const Args a = parse(argv, {"--topic", "--format"}, {"--wall"});
  if (a.positional.size() != 1 || !a.has("--topic"))
    throw std::invalid_argument("usage: hcosim export FILE --topic TOPIC [--format jsonl|csv] [--wall]");
  const std::string topic = a.get("--topic", ""), format = a.get("--format", "jsonl");
  if (format != "jsonl" && format != "csv") throw std::invalid_argument("--format must be jsonl or csv, not '" + format + "'");
  bool known = false;
  rt::with_topic(topic, [&](auto) { known = true; });
  if (!known) throw std::invalid_argument("unknown topic '" + topic + "'");

  rt::RecordingReader in(a.positional[0]);
  std::vector<rt::Record> records;
  std::uint64_t total = 0;
  for (rt::Record r; in.next(r); ++total)
    if (r.topic == topic) records.push_back(std::move(r));
  // Step order; samples of one step keep the order they were received in.
  std::stable_sort(records.begin(), records.end(),
                   [](const rt::Record& x, const rt::Record& y) { return x.step < y.step; });
  // Wall-clock fields differ between runs of the same deployment.
  const std::regex wall(R"(,"wall_time_ns":-?[0-9]+)");
  std::vector<std::string> header;
  for (const rt::Record& r : records) {
    std::string line;
    rt::with_topic(topic, [&](auto tag) {
      using T = typename decltype(tag)::type;
      line = to_json(rt::from_cdr<T>(r.cdr));
    });
    if (!a.has("--wall")) line = std::regex_replace(line, wall, "");
    if (format == "jsonl") {
      std::printf("%s\n", line.c_str());
      continue;
    }
    std::vector<std::pair<std::string, std::string>> cells;
    flatten(YAML::Load(line), "", cells);
    if (header.empty()) {
      std::string h;
      for (const auto& c : cells) header.push_back(c.first), h += (h.empty() ? "" : ",") + csv_field(c.first);
      std::printf("%s\n", h.c_str());
    }
    std::string row;
    for (std::size_t i = 0; i < cells.size(); ++i) row += (i ? "," : "") + csv_field(cells[i].second);
    std::printf("%s\n", row.c_str());
  }
  std::cerr << "hcosim export: " << records.size() << " " << topic << " samples of " << total << " in "
            << a.positional[0] << "\n";
  return 0;
}

}  // namespace hcosim::cli

// hcosim bench: suites that measure speed against error, written as
// DIR/SUITE.json: {"suite", "description", "machine", "rows": [{"name",
// "params", "metrics"}]}, plots as DIR/SUITE_ROW_*.png, and DIR/index.md
// reporting the suites of the run (bench_report.cc). Metric names carry their unit (p99_us,
// ms_per_sim_s, rel_error, ...).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <variant>

#include <yaml-cpp/yaml.h>

#include "adapters/json.h"
#include "services/bench/bench.h"
#include "services/cli/cli.h"

namespace fs = std::filesystem;

namespace hcosim::services::bench {
namespace {

const std::vector<Suite>& suites() {
  static const std::vector<Suite> all = {dds_suite(),   massspring_suite(), haptic_suite(), hybrid_suite(),
                                         rigid_suite(), tracking_suite(),   arview_suite(), soak_suite()};
  return all;
}

void write_json(const fs::path& dir, const Result& r) {
  adapters::Json j;
  j.begin_object()
      .key("suite")
      .value(r.suite->name)
      .key("description")
      .value(r.suite->what)
      .key("machine")
      .begin_object();
  for (const auto& [k, v] : r.machine) j.key(k).value(v);
  j.end_object().key("command").value(r.command).key("seconds").value(r.seconds).key("rows").begin_array();
  for (const auto& row : r.rows) {
    j.begin_object().key("name").value(row.name).key("params").begin_object();
    for (const auto& [k, v] : row.params) {
      j.key(k);
      std::visit([&](const auto& x) { j.value(x); }, v);
    }
    j.end_object().key("metrics").begin_object();
    for (const auto& [k, v] : row.metrics) j.key(k).value(v);
    j.end_object().end_object();
  }
  j.end_array().end_object();
  const fs::path file = dir / (std::string(r.suite->name) + ".json");
  std::ofstream(file) << j.str() << "\n";
  std::cout << "wrote " << file.string() << "\n";
}

// A suite's result as write_json wrote it (JSON read as YAML: quoted
// scalars are strings, plain ones numbers, null a metric not measured).
Result read_json(const fs::path& file, const Suite& s) {
  const YAML::Node doc = YAML::LoadFile(file.string());
  Result r{&s, {},  {}, doc["command"] ? doc["command"].as<std::string>() : "a run that did not record its command",
           {}, NAN, ""};
  for (const auto& kv : doc["machine"]) r.machine.emplace_back(kv.first.as<std::string>(), kv.second.as<std::string>());
  if (doc["seconds"] && !doc["seconds"].IsNull()) r.seconds = doc["seconds"].as<double>();
  for (const YAML::Node& row : doc["rows"]) {
    Row out{row["name"].as<std::string>(), {}, {}};
    for (const auto& kv : row["params"]) {
      const std::string k = kv.first.as<std::string>();
      if (kv.second.Tag() == "!")
        out.params.emplace_back(k, kv.second.as<std::string>());
      else
        out.params.emplace_back(k, kv.second.as<double>());
    }
    for (const auto& kv : row["metrics"])
      out.metrics.emplace_back(kv.first.as<std::string>(), kv.second.IsNull() ? NAN : kv.second.as<double>());
    r.rows.push_back(std::move(out));
  }
  return r;
}

// `bench report --out DIR`: the plots and index.md again from the JSON
// files of an earlier run, measuring nothing.
int report(const fs::path& dir) {
  std::vector<Result> results;
  for (const Suite& s : suites()) {
    const fs::path file = dir / (std::string(s.name) + ".json");
    if (!fs::exists(file)) continue;
    try {
      results.push_back(read_json(file, s));
    } catch (const YAML::Exception& e) {
      throw std::runtime_error(file.string() + ":" + std::to_string(e.mark.line + 1) +
                               ": not a bench report: " + e.msg);
    }
    results.back().figures = draw_plots(s, results.back().rows, dir);
  }
  if (results.empty()) throw std::invalid_argument("no SUITE.json of any suite in " + dir.string());
  write_index(dir, results, "hcosim bench report --out " + dir.string());
  return 0;
}

}  // namespace

int command(const std::vector<std::string>& argv) {
  const runtime::Args a = runtime::parse(argv, {"--out", "--domain"}, {"--quick"});
  if (a.positional.size() != 1) throw std::invalid_argument("bench needs one SUITE (or 'all', 'list' or 'report')");
  const std::string which = a.positional[0];
  if (which == "list") {
    for (const auto& s : suites()) std::cout << s.name << "\t" << s.what << "\n";
    return 0;
  }
  std::vector<const Suite*> chosen;
  std::string names;
  for (const auto& s : suites()) {
    names += (names.empty() ? "" : ", ") + std::string(s.name);
    if ((which == "all" && !s.alone) || which == s.name) chosen.push_back(&s);
  }
  if (!a.has("--out")) throw std::invalid_argument("bench needs --out DIR");
  const fs::path dir = a.get("--out", "");
  if (which == "report") return report(dir);
  if (chosen.empty()) throw std::invalid_argument("unknown suite '" + which + "' (suites: " + names + ", all)");
  fs::create_directories(dir);
  Context c;
  c.quick = a.switches.count("--quick") > 0;
  // Its own domain unless told: a benchmark must not hear a running deployment.
  c.domain = a.has("--domain") ? runtime::domain_of(a) : 200 + int(getpid() % 30);
  c.out = dir;
  std::string command = "hcosim bench";
  for (const auto& arg : argv) command += " " + arg;
  std::vector<Result> results;
  const auto begin = std::chrono::steady_clock::now();
  const auto since = [](auto t) { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(); };
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const Suite& s = *chosen[k];
    progress("[" + std::to_string(k + 1) + "/" + std::to_string(chosen.size()) + "] " + s.name + ": " + s.what);
    const auto t0 = std::chrono::steady_clock::now();
    Result r{&s, {}, {}, command, machine(), NAN, ""};
    try {
      r.rows = s.run(c);
      r.seconds = since(t0);
      r.figures = draw_plots(s, r.rows, dir);
      write_json(dir, r);
    } catch (const std::exception& e) {
      // One suite's failure must not cost the others' figures.
      if (chosen.size() == 1) throw;
      r.error = e.what();
      progress(std::string(s.name) + " failed: " + e.what());
    }
    progress(std::string(s.name) + " took " + text(std::round(since(t0))) + " s; " + text(std::round(since(begin))) +
             " s so far");
    results.push_back(std::move(r));
  }
  write_index(dir, results);
  for (const Result& r : results)
    if (!r.error.empty()) return 1;
  return 0;
}

}  // namespace hcosim::services::bench
